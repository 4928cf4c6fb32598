#pragma once
namespace gs {
inline constexpr const char* kVersion = "0.1.0";
}
