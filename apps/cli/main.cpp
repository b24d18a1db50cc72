// suffuse: the command-line front end. main() reads the options and calls a
// subcommand (commands.hpp; plot and gradation parse their own options).
//   suffuse run SCENE.json [--output DIR] [--threads N] [--quiet] [--checkpoint-every S] [--restart FILE]
//   suffuse validate SCENE.json
//   suffuse plugins
//   suffuse describe NAME
//   suffuse schema
//   suffuse plot --png OUT.png --x COLUMN --y COLUMN [options] FILE.csv [FILE.csv ...]
//   suffuse plot profile|map|animate [options] RUN
//   suffuse gradation PSD.csv [--json] [--png FILE.png]

#include <boost/program_options.hpp>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <optional>
#include <string>
#include <suffuse/error.hpp>
#include <suffuse/parallel.hpp>
#include <suffuse/version.hpp>

#include "commands.hpp"
#include "figures_module.hpp"
#include "gradation_command.hpp"
#if __has_include(<malloc.h>)
#include <malloc.h>  // glibc's mallopt
#endif

namespace po = boost::program_options;
namespace fs = std::filesystem;
using namespace suffuse::cli;

namespace {

const char* usage =
    "Usage:\n"
    "  suffuse run SCENE.json [--output DIR] [--threads N] [--quiet]\n"
    "                         [--checkpoint-every SECONDS] [--restart CHECKPOINT]\n"
    "                         run a scene; outputs go to DIR (default ./output/<scene name>);\n"
    "                         --restart continues a run from DIR/<scene>.checkpoint (a later end time extends it)\n"
    "  suffuse validate SCENE.json   check a scene against the plugin schemas, run nothing\n"
    "  suffuse element SCENE.json [--output DIR] [--quiet]\n"
    "                                drive one point of a phase along a test path (element test);\n"
    "                                writes DIR/<scene>[.<case>].element.csv (default ./output/<scene name>)\n"
    "  suffuse plugins               list the plugins found, with their libraries\n"
    "  suffuse describe NAME         print the parameters of a plugin (or a core section:\n"
    "                                scene, grid, time, body, output)\n"
    "  suffuse schema                every parameter of every plugin and section, as JSON\n"
    "  suffuse reference             the scene reference manual, as Markdown\n"
    "  suffuse plot --png OUT.png --x COLUMN --y COLUMN [--y COLUMN ...] [options] FILE.csv [FILE.csv ...]\n"
    "                                line charts of CSV columns (e.g. element-test results) to a PNG,\n"
    "                                no display needed; suffuse plot --help lists its options\n"
    "  suffuse plot profile --png OUT.png --field NAME --from X,Y --to X,Y [--times T,T,...] RUN\n"
    "                                a field along a line at several times (RUN: output directory or .pvd)\n"
    "  suffuse plot map --png OUT.png --field NAME [--times T,T,...] [--range MIN MAX] RUN\n"
    "                                a colour map of a field over the body (--slice of a 3D run)\n"
    "  suffuse plot animate --field NAME [--frames DIR] [--gif OUT.gif] RUN\n"
    "                                that map at every frame: numbered PNGs and an animated GIF\n"
    "                                (suffuse plot profile --help, ... list their options)\n"
    "  suffuse gradation PSD.csv [--json] [--png FILE.png]\n"
    "                                internal stability of a particle-size distribution by the published\n"
    "                                criteria (Kezdi, Kenney-Lau, Burenkova, ...); suffuse gradation --help\n"
    "Plugins are searched in the scene's plugin_paths, then $SUFFUSE_PLUGIN_PATH, then\n"
    "the bundled plugin directory.\n";

// Every output frame compresses each field with zlib, whose state (a few
// blocks of 64 KB) is freed after each field; glibc then gave the top of the
// heap back to the system each time, and every such return flushes the TLB of
// every processor running the program (threads of OpenMP and VTK): half of
// the default column's output stage. Freed memory is now kept for reuse up
// to 256 MB. Blocks of up to 32 MB come from the heap (glibc's own largest
// default once it adapts), larger ones are mapped and returned at once. The
// threads' own heaps (64 MB each) are then kept until the run ends: peak
// memory is what a run holds anyway.
void keep_freed_memory_for_reuse() {
#ifdef M_TRIM_THRESHOLD
  mallopt(M_MMAP_THRESHOLD, 32 << 20);
  mallopt(M_TRIM_THRESHOLD, 256 << 20);
#endif
}

}  // namespace

int main(int argc, char** argv) {
  keep_freed_memory_for_reuse();
  const suffuse::ParallelProcesses processes(argc, argv);  // mpirun: docs/parallel.md
  try {
    // plot has options and a list of files of its own.
    if (argc >= 2 && std::string(argv[1]) == "plot") return suffuse::figures::plot_command(argc - 1, argv + 1);
    if (argc >= 2 && std::string(argv[1]) == "gradation") return suffuse::gradation_command::run(argc - 1, argv + 1);
    po::options_description opts("Options");
    opts.add_options()("help,h", "show this help")("version", "print the version")(
        "output,o", po::value<std::string>(), "output directory (run)")(
        "threads,t", po::value<int>()->default_value(1), "number of threads (run)")(
        "quiet,q", "no progress line and no summary (run)")(
        "checkpoint-every", po::value<double>(),
        "simulated seconds between checkpoints, OUTPUT/<scene>.checkpoint (run; default: the scene's "
        "/time/checkpoint_interval; one is written at the end unless /time/checkpoint_at_end is false)")(
        "restart", po::value<std::string>(),
        "continue the run saved in this checkpoint; its outputs continue in the output directory (run)")(
        "newton",
        "print each quasi-static step's Newton iterations: the out-of-balance force relative to the forces, "
        "before the first solve and after each iteration (run)");
    po::options_description hidden;
    hidden.add_options()("command", po::value<std::string>())("argument", po::value<std::string>());
    po::options_description all;
    all.add(opts).add(hidden);
    po::positional_options_description positional;
    positional.add("command", 1).add("argument", 1);
    po::variables_map vm;
    po::store(po::command_line_parser(argc, argv).options(all).positional(positional).run(), vm);
    po::notify(vm);

    if (vm.count("help")) {
      std::cout << usage << "\n" << opts;
      return 0;
    }
    if (vm.count("version")) {
      std::cout << "suffuse " << suffuse::framework_version << " (plugin ABI " << suffuse::abi_major << "."
                << suffuse::abi_minor << ")\n";
      return 0;
    }
    if (!vm.count("command")) {
      std::cerr << usage;
      return 2;
    }
    const std::string command = vm["command"].as<std::string>();
    const bool has_arg = vm.count("argument") != 0;
    const std::string arg = has_arg ? vm["argument"].as<std::string>() : "";
    auto need_arg = [&](const char* what) {
      if (!has_arg) throw suffuse::Error(std::string("suffuse ") + command + " needs " + what);
    };
    if (command == "run") {
      need_arg("a scene file");
      const int threads = vm["threads"].as<int>();
      if (threads < 1) throw suffuse::Error("--threads must be at least 1");
      const fs::path out = vm.count("output") ? fs::path(vm["output"].as<std::string>())
                                              : fs::path("output") / fs::path(arg).stem();
      RunCommand run{out, threads, vm.count("quiet") != 0, std::nullopt, {}};
      if (vm.count("checkpoint-every")) {
        run.checkpoint_every = vm["checkpoint-every"].as<double>();
        if (!(*run.checkpoint_every > 0) || !std::isfinite(*run.checkpoint_every))
          throw suffuse::Error("--checkpoint-every must be a positive number of seconds");
      }
      if (vm.count("restart")) run.restart = vm["restart"].as<std::string>();
      run.newton = vm.count("newton") != 0;
      return cmd_run(arg, run);
    }
    if (command == "element") {
      need_arg("an element-test scene file");
      const fs::path out = vm.count("output") ? fs::path(vm["output"].as<std::string>())
                                              : fs::path("output") / fs::path(arg).stem();
      return cmd_element(arg, out, vm.count("quiet") != 0);
    }
    if (command == "validate") {
      need_arg("a scene file");
      return cmd_validate(arg);
    }
    if (command == "plugins") return cmd_plugins();
    if (command == "describe") {
      need_arg("a plugin name");
      return cmd_describe(arg);
    }
    if (command == "schema") return cmd_schema();
    if (command == "reference") return cmd_reference();
    std::cerr << "suffuse: unknown command '" << command << "'\n" << usage;
    return 2;
  } catch (const std::exception& e) {
    if (processes.size() == 1) {
      std::cerr << "suffuse: error: " << e.what() << "\n";
      return 1;
    }
    // The other processes may wait in an exchange this one will not join.
    std::cerr << "suffuse: error (process " << processes.rank() << " of " << processes.size() << "): " << e.what()
              << "\n";
    processes.abort(1);
  }

}
