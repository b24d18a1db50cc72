// The files suffuse plot writes: checked before anything is drawn, written
// under a temporary name and then renamed, so a reader never sees half a file
// and nothing is left behind on an error.
#pragma once

#include <filesystem>
#include <functional>

namespace suffuse::plot {

// Throws suffuse::Error unless FILE can be created: its directory exists and
// FILE is not a directory.
void check_output_path(const std::filesystem::path& file);

// Throws suffuse::Error unless the image size is a sane --width and --height.
void check_image_size(int width, int height);

// Calls WRITE with FILE + ".part", then renames that to FILE. On an error the
// part is removed and the error rethrown (as suffuse::Error).
void write_atomically(const std::filesystem::path& file, const std::function<void(const std::filesystem::path&)>& write);

}  // namespace suffuse::plot
