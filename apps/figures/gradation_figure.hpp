// The figure of suffuse gradation --png: the PSD on a log-size axis, and the
// Kenney-Lau shape curve H(F) with each criterion's boundary drawn on it.
#pragma once

#include <filesystem>
#include <suffuse/internal_stability.hpp>

namespace suffuse::gradation_figure {

// Draws offscreen and writes FILE (as FILE.part, then renamed: nothing is
// left on an error). Throws suffuse::Error.
void write_png(const Gradation& g, const InternalStability& s, const std::filesystem::path& file);

}  // namespace suffuse::gradation_figure
