// sun_spa_impl.hpp (private to libatmo) — internals of sun_spa.cpp that tests check.
#pragma once

namespace atmosh::atmo::detail {

// Range-reduced polynomial cosine used for the periodic-term sums; absolute error
// below 2e-15 for |x| < 1e6 (tested against std::cos).
double spa_cos(double x);

}  // namespace atmosh::atmo::detail
