// Animated GIF files (giflib): frames of a colour map played in a loop by any
// browser or image viewer, and inline in Markdown.
#pragma once

#include <vtkImageData.h>
#include <vtkSmartPointer.h>

#include <array>
#include <cstdint>
#include <filesystem>
#include <vector>

namespace suffuse::plot {

// The 256 colours of the GIF: viridis in 216 steps, then 40 greys from black
// to white (text, background, the edges between them). The images suffuse
// plot draws have no other colours but blends at edges, which take the
// nearest of these.
std::vector<std::array<std::uint8_t, 3>> gif_palette();

// Writes FRAMES (RGB images of one size, bottom row first as VTK keeps them)
// as a looping GIF, DELAY hundredths of a second per frame. Throws
// suffuse::Error.
void write_gif(const std::filesystem::path& file, const std::vector<vtkSmartPointer<vtkImageData>>& frames,
               int delay);

}  // namespace suffuse::plot
