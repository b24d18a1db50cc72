#include "subcommand_options.hpp"

#include <iostream>

namespace suffuse::subcommand {

namespace po = boost::program_options;

std::optional<Parsed> parse(int argc, char** argv, const po::options_description& options, const char* usage) {
  po::options_description hidden;
  hidden.add_options()("file", po::value<std::vector<std::string>>());
  po::options_description all;
  all.add(options).add(hidden);
  po::positional_options_description positional;
  positional.add("file", -1);
  Parsed parsed;
  po::store(po::command_line_parser(argc, argv).options(all).positional(positional).run(), parsed.options);
  po::notify(parsed.options);
  if (parsed.options.count("help")) {
    std::cout << usage << "\n" << options;
    return std::nullopt;
  }
  if (parsed.options.count("file")) parsed.files = parsed.options["file"].as<std::vector<std::string>>();
  return parsed;
}

}  // namespace suffuse::subcommand
