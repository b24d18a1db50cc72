// suffuse gradation PSD.csv [--json] [--png FILE]: the internal-stability
// criteria of a particle-size distribution, as a table or as JSON.
#pragma once

#include <iosfwd>
#include <suffuse/internal_stability.hpp>

namespace suffuse::gradation_command {

// ARGV[0] is "gradation". Returns the exit status; throws suffuse::Error.
int run(int argc, char** argv);

// The table `suffuse gradation` prints (criterion, value, verdict,
// applicability), also printed by `suffuse validate` for a body's gradation.
void print_table(std::ostream& out, const InternalStability& s, const std::string& indent = "");

}  // namespace suffuse::gradation_command
