// Option parsing shared by the subcommands that take their own options and a
// list of files (suffuse plot, suffuse gradation).
#pragma once

#include <boost/program_options.hpp>
#include <optional>
#include <string>
#include <vector>

namespace suffuse::subcommand {

struct Parsed {
  boost::program_options::variables_map options;
  std::vector<std::string> files;  // the arguments that are not options, in order
};

// Parses ARGV (ARGV[0] is the subcommand's name) against OPTIONS, every other
// argument being a file. With --help (OPTIONS must declare "help"), prints
// USAGE and OPTIONS to standard output and returns nothing.
std::optional<Parsed> parse(int argc, char** argv, const boost::program_options::options_description& options,
                            const char* usage);

}  // namespace suffuse::subcommand
