#pragma once
namespace gs::inline core {
// The project's version, from CMake's project(VERSION ...).
inline constexpr const char* kVersion = GS_VERSION;
}
