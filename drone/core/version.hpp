#pragma once
namespace gs::inline core {
inline constexpr const char* kVersion = "0.1.0";
}
