#include "drone/sim/texture.hpp"

#include "drone/sim/rng.hpp"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <array>
#include <cmath>

namespace gs::sim {
namespace {

constexpr std::array<std::pair<TextureKind, std::string_view>, 13> kNames{{
    {TextureKind::Plain, "plain"},
    {TextureKind::Noise, "noise"},
    {TextureKind::Checker, "checker"},
    {TextureKind::Bricks, "bricks"},
    {TextureKind::Tiles, "tiles"},
    {TextureKind::Wood, "wood"},
    {TextureKind::Concrete, "concrete"},
    {TextureKind::Tape, "tape"},
    {TextureKind::Paper, "paper"},
    {TextureKind::Posters, "posters"},
    {TextureKind::Ceiling, "ceiling"},
    {TextureKind::Cardboard, "cardboard"},
    {TextureKind::Stripes, "stripes"},
}};

cv::Scalar bgr(cv::Vec3b rgb) {
    return {double(rgb[2]), double(rgb[1]), double(rgb[0])};
}

cv::Scalar jitter(Rng& rng, cv::Scalar c, double amount) {
    const double k = 1.0 + rng.uniform(-amount, amount);
    return {std::clamp(c[0] * k, 0.0, 255.0), std::clamp(c[1] * k, 0.0, 255.0),
            std::clamp(c[2] * k, 0.0, 255.0)};
}

// Tileable value noise in [0, 1]: a random cells x cells grid, wrapped and cubic-upsampled.
cv::Mat value_noise(Rng& rng, int size, int cells_x, int cells_y) {
    cv::Mat grid(cells_y, cells_x, CV_32F);
    for (int y = 0; y < cells_y; ++y)
        for (int x = 0; x < cells_x; ++x) grid.at<float>(y, x) = float(rng.uniform());
    cv::Mat padded;
    cv::copyMakeBorder(grid, padded, 2, 2, 2, 2, cv::BORDER_WRAP);
    const double sx = double(size) / cells_x, sy = double(size) / cells_y;
    cv::Mat up;
    cv::resize(padded, up,
               cv::Size(int(std::lround(padded.cols * sx)), int(std::lround(padded.rows * sy))), 0,
               0, cv::INTER_CUBIC);
    const cv::Rect roi(int(std::lround(2 * sx)), int(std::lround(2 * sy)), size, size);
    return up(roi).clone();
}

// Fractal sum of octaves, normalised to [0, 1].
cv::Mat fbm(Rng& rng, int size, int base_cells, int octaves, double aspect = 1.0) {
    cv::Mat acc = cv::Mat::zeros(size, size, CV_32F);
    double amp = 1.0, total = 0.0;
    int cells = base_cells;
    for (int o = 0; o < octaves && cells <= size / 2; ++o) {
        const int cy = std::max(1, int(std::lround(cells * aspect)));
        acc += value_noise(rng, size, cells, std::min(cy, size / 2)) * amp;
        total += amp;
        amp *= 0.5;
        cells *= 2;
    }
    acc /= total;
    double lo = 0, hi = 1;
    cv::minMaxLoc(acc, &lo, &hi);
    if (hi > lo) acc = (acc - lo) / (hi - lo);
    return acc;
}

// img = img * (1 - a*(0.5 - n)) per pixel: modulate brightness by noise n in [0, 1].
void modulate(cv::Mat& img, const cv::Mat& n, double amount) {
    cv::Mat gain = 1.0 + (n - 0.5) * amount;
    std::vector<cv::Mat> ch;
    cv::split(img, ch);
    for (auto& c : ch) {
        cv::Mat f;
        c.convertTo(f, CV_32F);
        f = f.mul(gain);
        f.convertTo(c, CV_8U);
    }
    cv::merge(ch, img);
}

void speckle(Rng& rng, cv::Mat& img, int count, int rmin, int rmax, cv::Scalar c, double jit) {
    for (int i = 0; i < count; ++i) {
        const cv::Point p(rng.range(0, img.cols - 1), rng.range(0, img.rows - 1));
        cv::circle(img, p, rng.range(rmin, rmax), jitter(rng, c, jit), cv::FILLED, cv::LINE_AA);
    }
}

void rotated_rect(cv::Mat& img, cv::Point2d c, cv::Size2d s, double angle_deg, cv::Scalar col) {
    cv::Point2f pts[4];
    cv::RotatedRect(cv::Point2f(c), cv::Size2f(s), float(angle_deg)).points(pts);
    cv::Point ip[4];
    for (int i = 0; i < 4; ++i)
        ip[i] = cv::Point(int(std::lround(pts[i].x)), int(std::lround(pts[i].y)));
    cv::fillConvexPoly(img, ip, 4, col, cv::LINE_AA);
    // Draw wrapped copies so the texture tiles.
    for (int dx = -1; dx <= 1; ++dx)
        for (int dy = -1; dy <= 1; ++dy) {
            if (dx == 0 && dy == 0) continue;
            cv::Point jp[4];
            for (int i = 0; i < 4; ++i) jp[i] = ip[i] + cv::Point(dx * img.cols, dy * img.rows);
            cv::fillConvexPoly(img, jp, 4, col, cv::LINE_AA);
        }
}

void text(cv::Mat& img, const std::string& s, cv::Point org, double scale, cv::Scalar col,
          int thick) {
    cv::putText(img, s, org, cv::FONT_HERSHEY_SIMPLEX, scale, col, thick, cv::LINE_AA);
}

std::string random_word(Rng& rng, int len) {
    static constexpr char kLetters[] = "ABCDEFGHKLMNOPRSTUVWXZ0123456789";
    std::string s;
    for (int i = 0; i < len; ++i) s += kLetters[rng.range(0, int(sizeof(kLetters)) - 2)];
    return s;
}

cv::Mat make_bricks(Rng& rng, int S, cv::Scalar brick, cv::Scalar mortar) {
    cv::Mat img(S, S, CV_8UC3, mortar);
    const int rows = 8, cols = 4;
    const int bh = S / rows, bw = S / cols, m = std::max(2, S / 128);
    for (int r = 0; r < rows; ++r) {
        const int off = (r % 2) ? bw / 2 : 0;
        for (int c = -1; c < cols; ++c) {
            const int x0 = c * bw + off;
            const cv::Scalar col = jitter(rng, brick, 0.18);
            cv::rectangle(img, cv::Rect(x0 + m / 2, r * bh + m / 2, bw - m, bh - m), col,
                          cv::FILLED);
            if (x0 < 0)
                cv::rectangle(img, cv::Rect(x0 + S + m / 2, r * bh + m / 2, bw - m, bh - m), col,
                              cv::FILLED);
        }
    }
    modulate(img, fbm(rng, S, 16, 4), 0.35);
    return img;
}

cv::Mat make_tiles(Rng& rng, int S, cv::Scalar tile, cv::Scalar grout) {
    cv::Mat img(S, S, CV_8UC3, grout);
    const int n = 4, t = S / n, g = std::max(2, S / 170);
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x)
            cv::rectangle(img, cv::Rect(x * t + g, y * t + g, t - 2 * g, t - 2 * g),
                          jitter(rng, tile, 0.08), cv::FILLED);
    speckle(rng, img, S / 2, 1, 2, tile * 0.6, 0.3);
    speckle(rng, img, S / 8, 1, 3, tile * 1.25, 0.2);
    modulate(img, fbm(rng, S, 8, 4), 0.25);
    return img;
}

cv::Mat make_wood(Rng& rng, int S, cv::Scalar wood) {
    cv::Mat img(S, S, CV_8UC3, wood);
    const int planks = 6, pw = S / planks;
    for (int p = 0; p < planks; ++p) {
        const cv::Scalar col = jitter(rng, wood, 0.15);
        const int seam = rng.range(0, S - 1);
        cv::rectangle(img, cv::Rect(p * pw, 0, pw, S), col, cv::FILLED);
        cv::line(img, {p * pw, 0}, {p * pw, S}, col * 0.45, 2);
        cv::line(img, {p * pw, seam}, {p * pw + pw, seam}, col * 0.45, 2);
        for (int k = 0; k < 3; ++k)  // knots
            cv::ellipse(img, cv::Point(p * pw + rng.range(4, pw - 4), rng.range(0, S - 1)),
                        cv::Size(rng.range(2, 5), rng.range(4, 10)), 0, 0, 360, col * 0.55,
                        cv::FILLED, cv::LINE_AA);
    }
    // Grain: noise stretched along the planks.
    modulate(img, fbm(rng, S, 32, 3, 1.0 / 16), 0.45);
    modulate(img, fbm(rng, S, 8, 3), 0.2);
    return img;
}

cv::Mat make_concrete(Rng& rng, int S, cv::Scalar base) {
    cv::Mat img(S, S, CV_8UC3, base);
    modulate(img, fbm(rng, S, 4, 6), 0.45);
    speckle(rng, img, S / 3, 1, 2, base * 0.55, 0.2);
    speckle(rng, img, S / 40, 2, 4, base * 0.5, 0.2);
    return img;
}

cv::Mat make_tape(Rng& rng, int S, cv::Scalar cloth, cv::Scalar tape) {
    cv::Mat img(S, S, CV_8UC3, cloth);
    modulate(img, fbm(rng, S, 8, 4), 0.5);
    const int n = 70;
    for (int i = 0; i < n; ++i) {
        const double w = rng.uniform(S * 0.03, S * 0.09), h = rng.uniform(S * 0.015, S * 0.03);
        rotated_rect(img, {rng.uniform(0, S), rng.uniform(0, S)}, {w, h}, rng.uniform(0, 180),
                     jitter(rng, tape, 0.06));
    }
    return img;
}

cv::Mat make_paper(Rng& rng, int S, cv::Scalar base, cv::Scalar paper) {
    cv::Mat img = make_concrete(rng, S, base);
    const int n = 6;
    for (int i = 0; i < n; ++i) {
        const double w = rng.uniform(S * 0.12, S * 0.2);
        rotated_rect(img, {rng.uniform(0, S), rng.uniform(0, S)}, {w, w * 1.41},
                     rng.uniform(-12, 12), jitter(rng, paper, 0.04));
    }
    return img;
}

cv::Mat make_posters(Rng& rng, int S, cv::Scalar wall, cv::Scalar accent) {
    cv::Mat img(S, S, CV_8UC3, wall);
    modulate(img, fbm(rng, S, 4, 5), 0.12);
    const int n = rng.range(2, 4);
    for (int i = 0; i < n; ++i) {
        const int w = rng.range(S / 7, S / 4), h = int(w * 1.4);
        const int x = (S / n) * i + rng.range(4, std::max(5, S / n - w - 4));
        const int y = rng.range(S / 6, std::max(S / 6 + 1, S / 2 - h / 2));
        const cv::Rect r(x, y, w, h);
        const cv::Scalar bg = jitter(rng, i % 2 ? accent : cv::Scalar(235, 235, 235), 0.15);
        cv::rectangle(img, r, bg, cv::FILLED);
        cv::rectangle(img, r, bg * 0.5, 2);
        const cv::Scalar fg(rng.range(20, 220), rng.range(20, 220), rng.range(20, 220));
        const int kind = rng.range(0, 2);
        if (kind == 0) {
            cv::circle(img, {x + w / 2, y + h / 3}, w / 4, fg, cv::FILLED, cv::LINE_AA);
        } else if (kind == 1) {
            for (int k = 0; k < 4; ++k)
                cv::rectangle(img, cv::Rect(x + w / 8 + k * w / 5, y + h / 6, w / 7, h / 3),
                              fg * (0.6 + 0.1 * k), cv::FILLED);
        } else {
            const cv::Point tri[3] = {
                {x + w / 2, y + h / 10}, {x + w / 8, y + h / 2}, {x + 7 * w / 8, y + h / 2}};
            cv::fillConvexPoly(img, tri, 3, fg, cv::LINE_AA);
        }
        text(img, random_word(rng, 4), {x + w / 10, y + h * 3 / 4}, w / 110.0, bg * 0.2,
             std::max(1, w / 50));
        for (int k = 0; k < 2; ++k)
            cv::line(img, {x + w / 10, y + h * 4 / 5 + k * h / 14 + h / 20},
                     {x + w * 9 / 10, y + h * 4 / 5 + k * h / 14 + h / 20}, bg * 0.4, 1);
    }
    // Skirting and a light switch add corners near the floor and at hand height.
    cv::rectangle(img, cv::Rect(0, S - S / 24, S, S / 24), wall * 0.55, cv::FILLED);
    const int sx = rng.range(0, S - 20);
    cv::rectangle(img, cv::Rect(sx, S * 11 / 20, S / 40, S / 30), cv::Scalar(240, 240, 240),
                  cv::FILLED);
    return img;
}

cv::Mat make_ceiling(Rng& rng, int S, cv::Scalar tile) {
    cv::Mat img(S, S, CV_8UC3, tile * 0.7);
    const int n = 4, t = S / n, g = std::max(2, S / 128);
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x) {
            const bool light = rng.chance(0.12);
            const cv::Scalar c = light ? cv::Scalar(252, 252, 250) : jitter(rng, tile, 0.04);
            cv::rectangle(img, cv::Rect(x * t + g, y * t + g, t - 2 * g, t - 2 * g), c, cv::FILLED);
            if (light)
                for (int k = 1; k < 4; ++k)
                    cv::line(img, {x * t + g, y * t + k * t / 4},
                             {x * t + t - g, y * t + k * t / 4}, cv::Scalar(215, 215, 215), 1);
        }
    speckle(rng, img, S, 1, 1, tile * 0.75, 0.1);
    return img;
}

cv::Mat make_cardboard(Rng& rng, int S, cv::Scalar board) {
    cv::Mat img(S, S, CV_8UC3, board);
    modulate(img, fbm(rng, S, 8, 4, 0.25), 0.25);
    const int tw = S / 10;
    cv::rectangle(img, cv::Rect(0, S / 2 - tw / 2, S, tw), jitter(rng, board * 1.15, 0.05),
                  cv::FILLED);
    const cv::Rect label(rng.range(S / 10, S / 2), rng.range(S / 10, S / 4), S / 3, S / 5);
    cv::rectangle(img, label, cv::Scalar(238, 238, 238), cv::FILLED);
    text(img, random_word(rng, 5), {label.x + 6, label.y + label.height / 3}, S / 700.0,
         {30, 30, 30}, 2);
    for (int k = 0; k < 18; ++k) {
        const int x = label.x + 8 + k * (label.width - 16) / 18;
        cv::line(img, {x, label.y + label.height / 2}, {x, label.y + label.height - 6},
                 {20, 20, 20}, rng.range(1, 3));
    }
    // Printed arrows ("this side up") for a few strong corners.
    const cv::Point a(rng.range(S / 8, S - S / 4), S * 3 / 4);
    const cv::Point tri[3] = {{a.x, a.y - S / 12}, {a.x - S / 20, a.y}, {a.x + S / 20, a.y}};
    cv::fillConvexPoly(img, tri, 3, board * 0.35, cv::LINE_AA);
    cv::rectangle(img, cv::Rect(a.x - S / 60, a.y, S / 30, S / 14), board * 0.35, cv::FILLED);
    return img;
}

cv::Mat make_stripes(Rng& rng, int S, cv::Scalar a, cv::Scalar b) {
    cv::Mat img(S, S, CV_8UC3, a);
    const int n = 8, w = S / n;
    for (int i = -n; i < 2 * n; i += 2) {
        const cv::Point p[4] = {{i * w, 0}, {i * w + w, 0}, {i * w + w + S, S}, {i * w + S, S}};
        cv::fillConvexPoly(img, p, 4, b, cv::LINE_AA);
    }
    modulate(img, fbm(rng, S, 8, 4), 0.2);
    speckle(rng, img, S / 16, 1, 3, b, 0.3);
    return img;
}

void pyr_down_wrap(const cv::Mat& src, cv::Mat& dst) {
    cv::Mat padded, down;
    cv::copyMakeBorder(src, padded, 4, 4, 4, 4, cv::BORDER_WRAP);
    cv::pyrDown(padded, down);
    dst = down(cv::Rect(2, 2, src.cols / 2, src.rows / 2)).clone();
}

std::vector<std::uint32_t> pack(const cv::Mat& bgr) {
    std::vector<std::uint32_t> out(std::size_t(bgr.rows) * std::size_t(bgr.cols));
    for (int y = 0; y < bgr.rows; ++y) {
        const auto* row = bgr.ptr<cv::Vec3b>(y);
        for (int x = 0; x < bgr.cols; ++x)
            out[std::size_t(y) * std::size_t(bgr.cols) + std::size_t(x)] =
                std::uint32_t(row[x][0]) | (std::uint32_t(row[x][1]) << 8) |
                (std::uint32_t(row[x][2]) << 16);
    }
    return out;
}

}  // namespace

std::string_view to_string(TextureKind k) {
    for (const auto& [kind, name] : kNames)
        if (kind == k) return name;
    return "unknown";
}

std::optional<TextureKind> texture_kind_from_string(std::string_view s) {
    for (const auto& [kind, name] : kNames)
        if (name == s) return kind;
    return std::nullopt;
}

cv::Mat generate_texture_image(const TextureSpec& spec, int S) {
    Rng rng(mix_seed(spec.seed, std::uint64_t(spec.kind) + 1));
    const cv::Scalar c1 = bgr(spec.color_rgb);
    auto c2 = [&](cv::Vec3b def) { return bgr(spec.has_color2 ? spec.color2_rgb : def); };
    cv::Mat img;
    switch (spec.kind) {
        case TextureKind::Plain:
            img = cv::Mat(S, S, CV_8UC3, c1);
            modulate(img, fbm(rng, S, 4, 5), 0.08);
            break;
        case TextureKind::Noise: {
            const cv::Mat n = fbm(rng, S, 8, 5);
            img = cv::Mat(S, S, CV_8UC3);
            const cv::Scalar b = c2({40, 40, 40});
            for (int y = 0; y < S; ++y)
                for (int x = 0; x < S; ++x) {
                    const float t =
                        std::clamp((n.at<float>(y, x) - 0.5f) * 3.0f + 0.5f, 0.0f, 1.0f);
                    for (int ch = 0; ch < 3; ++ch)
                        img.at<cv::Vec3b>(y, x)[ch] =
                            cv::saturate_cast<uchar>(c1[ch] * double(t) + b[ch] * double(1 - t));
                }
            speckle(rng, img, S / 6, 1, 3, b, 0.2);
            speckle(rng, img, S / 6, 1, 3, c1, 0.2);
            break;
        }
        case TextureKind::Checker: {
            img = cv::Mat(S, S, CV_8UC3, c1);
            const int n = 8, t = S / n;
            for (int y = 0; y < n; ++y)
                for (int x = 0; x < n; ++x)
                    if ((x + y) % 2)
                        cv::rectangle(img, cv::Rect(x * t, y * t, t, t), c2({30, 30, 30}),
                                      cv::FILLED);
            break;
        }
        case TextureKind::Bricks:
            img = make_bricks(rng, S, c1, c2({190, 185, 175}));
            break;
        case TextureKind::Tiles:
            img = make_tiles(rng, S, c1, c2({90, 90, 90}));
            break;
        case TextureKind::Wood:
            img = make_wood(rng, S, c1);
            break;
        case TextureKind::Concrete:
            img = make_concrete(rng, S, c1);
            break;
        case TextureKind::Tape:
            img = make_tape(rng, S, c1, c2({240, 240, 235}));
            break;
        case TextureKind::Paper:
            img = make_paper(rng, S, c1, c2({245, 245, 240}));
            break;
        case TextureKind::Posters:
            img = make_posters(rng, S, c1, c2({200, 60, 50}));
            break;
        case TextureKind::Ceiling:
            img = make_ceiling(rng, S, c1);
            break;
        case TextureKind::Cardboard:
            img = make_cardboard(rng, S, c1);
            break;
        case TextureKind::Stripes:
            img = make_stripes(rng, S, c1, c2({25, 25, 25}));
            break;
    }
    return img;
}

Texture make_texture(const TextureSpec& spec, int size) {
    Texture t;
    t.size = size;
    cv::Mat level = generate_texture_image(spec, size);
    // A slight pre-blur: the camera's optics are soft and it keeps level 0 from aliasing.
    cv::Mat padded;
    cv::copyMakeBorder(level, padded, 3, 3, 3, 3, cv::BORDER_WRAP);
    cv::GaussianBlur(padded, padded, cv::Size(5, 5), 0.7);
    level = padded(cv::Rect(3, 3, size, size)).clone();
    while (true) {
        t.levels.push_back(pack(level));
        if (level.cols <= 4) break;
        cv::Mat next;
        pyr_down_wrap(level, next);
        level = next;
    }
    return t;
}

}  // namespace gs::sim
