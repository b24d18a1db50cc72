// The files suffuse plot writes (see output_file.hpp).
#include "output_file.hpp"

#include <string>
#include <suffuse/error.hpp>
#include <system_error>

namespace suffuse::plot {

namespace fs = std::filesystem;

void check_output_path(const fs::path& file) {
  const fs::path dir = file.has_parent_path() ? file.parent_path() : fs::path(".");
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) throw Error("cannot write " + file.string() + ": no directory " + dir.string());
  if (fs::is_directory(file, ec)) throw Error("cannot write " + file.string() + ": it is a directory");
}

void check_image_size(int width, int height) {
  constexpr int max_pixels = 10000;
  if (width < 100 || width > max_pixels || height < 100 || height > max_pixels)
    throw Error("--width and --height must be between 100 and " + std::to_string(max_pixels) + " pixels");
}

void write_atomically(const fs::path& file, const std::function<void(const fs::path&)>& write) {
  const fs::path part = file.string() + ".part";
  std::error_code ec;
  try {
    write(part);
    fs::rename(part, file);
  } catch (const std::exception& e) {
    fs::remove(part, ec);
    if (dynamic_cast<const Error*>(&e)) throw;
    throw Error("cannot write " + file.string() + ": " + e.what());
  }
}

}  // namespace suffuse::plot
