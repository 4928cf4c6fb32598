#pragma once
// Procedural textures for the simulated scene: generated from a seed at load time (bricks,
// tiles, wood, tape on cloth as in the thesis' obstacle, posters ...), tileable, pre-blurred and
// mip-mapped so the renderer can sample without aliasing. Every kind carries corners for a
// Shi-Tomasi detector.

#include <opencv2/core.hpp>

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace gs::sim {

enum class TextureKind {
    Plain,      // flat colour with faint noise (little texture: a hard case)
    Noise,      // two-colour blotches and speckles
    Checker,    // 8x8 checkerboard
    Bricks,     // running-bond bricks with mortar
    Tiles,      // floor tiles with grout
    Wood,       // planks with grain
    Concrete,   // grey mottled concrete with pits
    Tape,       // black cloth with small white tape pieces (thesis' uncluttered obstacle)
    Paper,      // concrete with white paper sheets taped on (thesis' cluttered pillars)
    Posters,    // painted wall with posters
    Ceiling,    // suspended ceiling tiles with light panels
    Cardboard,  // boxes: brown board, tape strip, label
    Stripes,    // yellow/black hazard stripes
};

std::string_view to_string(TextureKind k);
std::optional<TextureKind> texture_kind_from_string(std::string_view s);

struct TextureSpec {
    TextureKind kind = TextureKind::Noise;
    std::uint64_t seed = 1;
    double scale_m = 1.0;                // physical size of one (square) repeat
    cv::Vec3b color_rgb{160, 160, 160};  // main colour
    cv::Vec3b color2_rgb{0, 0, 0};       // secondary colour, used when has_color2
    bool has_color2 = false;             // else a kind-specific default

    bool operator==(const TextureSpec&) const = default;
};

// Generated texture: power-of-two square BGR levels, level 0 first.
struct Texture {
    int size = 0;                                    // level 0 side, a power of two
    std::vector<std::vector<std::uint32_t>> levels;  // packed 0x00RRGGBB, row-major
};

// The level-0 image (BGR, size x size), deterministic for a spec.
cv::Mat generate_texture_image(const TextureSpec& spec, int size = 512);

// Image + pre-blur + wrap-around mip chain.
Texture make_texture(const TextureSpec& spec, int size = 512);

}  // namespace gs::sim
