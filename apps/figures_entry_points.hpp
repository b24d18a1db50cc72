#pragma once
// What the figures module exports, by name (figures_entry_points.cpp), and
// the app finds (figures_module.cpp).
#include <filesystem>
#include <suffuse/gradation.hpp>
#include <suffuse/internal_stability.hpp>

namespace suffuse::figures {

using PlotCommand = int(int argc, char** argv);
using WriteGradationPng = void(const Gradation&, const InternalStability&, const std::filesystem::path&);

}  // namespace suffuse::figures
