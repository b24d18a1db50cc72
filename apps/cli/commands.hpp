#pragma once
// The subcommands of the suffuse command line (main.cpp reads the options
// and calls one of these). Each returns the exit status and throws
// suffuse::Error for what the user must fix.
#include <filesystem>
#include <optional>
#include <ostream>
#include <string>

#include <suffuse/scene.hpp>

namespace suffuse::cli {

// catalogue_commands.cpp: what the plugins and the scene's sections take.
int cmd_plugins();
int cmd_describe(const std::string& name);
int cmd_schema();
int cmd_reference();

// validate_command.cpp
int cmd_validate(const std::filesystem::path& scene_file);
// A body whose erodible fines, all washed out, would leave a porosity no soil
// skeleton has; `run` warns of it too.
void warn_about_open_skeletons(const Scene& scene, std::ostream& out);

// element_command.cpp
int cmd_element(const std::filesystem::path& scene_file, const std::filesystem::path& output, bool quiet);

// run_command.cpp: what `suffuse run` takes besides the scene.
struct RunCommand {
  std::filesystem::path output;
  int threads = 1;
  bool quiet = false;
  std::optional<double> checkpoint_every;  // [s] of simulated time
  std::filesystem::path restart;           // a checkpoint to continue from
  bool newton = false;                     // print each quasi-static step's Newton residuals
};
int cmd_run(const std::filesystem::path& scene_file, const RunCommand& command);

}  // namespace suffuse::cli
