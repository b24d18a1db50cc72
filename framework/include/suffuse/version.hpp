#pragma once
// Versions of the framework and of the plugin ABI.
// A plugin built against another ABI major version is refused at load time;
// minor versions only add to the SDK, so a newer core loads older-minor plugins.

namespace suffuse {

inline constexpr int abi_major = 21;
inline constexpr int abi_minor = 1;
inline constexpr const char* framework_version = "0.21.9";

}  // namespace suffuse
