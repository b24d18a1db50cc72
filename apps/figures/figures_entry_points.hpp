#pragma once
// What the figures module exports, by name (figures_entry_points.cpp), and
// the app finds (figures_module.cpp).
#include <filesystem>
#include <suffuse/gradation.hpp>
#include <suffuse/internal_stability.hpp>

namespace suffuse::figures {

using PlotCommand = int(int argc, char** argv);
using WriteGradationPng = void(const Gradation&, const InternalStability&, const std::filesystem::path&);
// The suffuse version the module was built with: a module of another build
// is refused (the SDK types it takes are this build's).
using ModuleVersion = const char*();

}  // namespace suffuse::figures
