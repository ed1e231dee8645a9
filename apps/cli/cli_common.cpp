#include "cli_common.hpp"

#include <cmath>
#include <cstdlib>
#include <iostream>
#include <sstream>

#include "atmosh/error.hpp"
#include "atmosh/parallel.hpp"
#include "atmosh/io/provenance.hpp"

namespace atmosh::cli {

void print_json(const nlohmann::json& j) { std::cout << j.dump(2) << std::endl; }

std::vector<double> parse_list(const std::string& text, const std::string& what) {
  std::vector<double> out;
  std::stringstream ss(text);
  std::string item;
  while (std::getline(ss, item, ',')) {
    const char* b = item.c_str();
    char* e = nullptr;
    const double v = std::strtod(b, &e);
    while (e && *e == ' ') ++e;
    if (e == b || *e != '\0' || !std::isfinite(v))
      throw InputError(what + ": '" + text + "' is not a list of finite numbers");
    out.push_back(v);
  }
  if (out.empty()) throw InputError(what + ": '" + text + "' is empty");
  return out;
}

std::array<double, 3> parse_triple(const std::string& text, const std::string& what) {
  const auto v = parse_list(text, what);
  if (v.size() != 3) throw InputError(what + ": '" + text + "' is not three numbers x,y,z");
  return {v[0], v[1], v[2]};
}

std::array<int, 2> parse_size(const std::string& text, const std::string& what) {
  const auto x = text.find_first_of("xX");
  auto bad = [&] { return InputError(what + ": '" + text + "' is not a size WxH (each 1..65536)"); };
  if (x == std::string::npos) throw bad();
  try {
    std::size_t p1 = 0, p2 = 0;
    const std::string a = text.substr(0, x), b = text.substr(x + 1);
    const long w = std::stol(a, &p1), h = std::stol(b, &p2);
    if (p1 != a.size() || p2 != b.size() || w < 1 || h < 1 || w > 65536 || h > 65536) throw bad();
    return {static_cast<int>(w), static_cast<int>(h)};
  } catch (const std::logic_error&) {
    throw bad();
  }
}

double require_range(double v, double lo, double hi, const std::string& what) {
  if (!std::isfinite(v) || v < lo || v > hi)
    throw InputError(what + ": " + io::format_double(v) + " is out of range [" + io::format_double(lo) + ", " +
                     io::format_double(hi) + "]");
  return v;
}

int threads_option(int requested, const std::string& option) {
  if (requested < 0 || requested > 1024)
    throw InputError(option + " " + std::to_string(requested) + ": must be in 0..1024 (0 = the " +
                     std::to_string(available_cpus()) + " CPUs this process may use)");
  const int n = resolve_threads(requested);
  io::set_threads(n);
  return n;
}

void check_device(const std::string& device) {
  if (device != "cpu" && device != "gpu" && device != "auto")
    throw InputError("--device " + device + ": must be cpu, gpu or auto");
}

}  // namespace atmosh::cli
