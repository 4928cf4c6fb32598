#pragma once
// Shared by the libFuzzer targets (tests/fuzz/*_fuzz.cpp, built with -DGS_FUZZ=ON under clang):
// a check that stops the run with a message when an invariant breaks (a finding, not a crash of
// the parser under test), and the input cut into a selector and the rest.

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <span>
#include <string>

namespace gs::fuzz {

#define GS_FUZZ_CHECK(cond)                                                              \
    do {                                                                                 \
        if (!(cond)) {                                                                   \
            std::fprintf(stderr, "fuzz invariant failed: %s (%s:%d)\n", #cond, __FILE__, \
                         __LINE__);                                                      \
            std::abort();                                                                \
        }                                                                                \
    } while (0)

// The first byte picks one of `choices` readers; the rest is their input.
struct Split {
    unsigned choice = 0;
    std::span<const std::uint8_t> rest;
    std::string text() const { return std::string(rest.begin(), rest.end()); }
};
inline Split split(const std::uint8_t* data, std::size_t size, unsigned choices) {
    if (size == 0) return {};
    return {static_cast<unsigned>(data[0]) % choices, std::span(data + 1, size - 1)};
}

}  // namespace gs::fuzz
