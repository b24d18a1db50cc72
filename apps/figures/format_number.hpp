// Numbers in the messages and labels of suffuse plot, as a stream writes them
// by default (six significant digits: 0.05, 12.5, 1e-06).
#pragma once

#include <sstream>
#include <string>

namespace suffuse::plot {

inline std::string format_number(double v) {
  std::ostringstream out;
  out << v;
  return out.str();
}

}  // namespace suffuse::plot
