// atmosh/format.hpp — the one number formatter of every text output (CSV cells,
// JSON written by hand, provenance lines, sweep parameter columns, messages).
//
// format_double(v) is the shortest decimal string that reads back to exactly v
// (std::to_chars' shortest round-trip form, so 8e-6 prints as "8e-06": exponents
// have at least two digits and a sign, as printf's %g), "nan", "inf", "-inf" for
// non-finite values. Integers print without a decimal point ("16", "1e+22").
#pragma once

#include <string>

namespace atmosh {

std::string format_double(double v);

}  // namespace atmosh
