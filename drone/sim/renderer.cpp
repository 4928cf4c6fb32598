#include "drone/sim/renderer.hpp"
#include "drone/core/geometry.hpp"
#include "drone/sim/units.hpp"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstring>
#include <limits>
#include <numbers>
#include <vector>

namespace gs::sim {
namespace {

constexpr int kBlock = 8;
constexpr double kNear = 0.01;
constexpr std::uint16_t kNoPrim = 0xffff;

// Internal frame: world FRD (drone/core/geometry.hpp); the scene's z-up heights map to it.
cv::Vec3d frd(double x, double y, double z_up) {
    return geom::to_cv(geom::world_point(x, y, z_up));
}
const cv::Vec3d kDown{0, 0, 1};

struct Prim {
    cv::Vec3d p0, eu, ev, n;  // origin (top-left seen from outside), unit axes, outward normal
    double lu = 0, lv = 0;    // extents in metres (disc: lu = radius, centre at p0)
    bool disc = false;
    int tex = 0;
    double tu = 1, tv = 1;  // texels (level 0) per metre
    double ou = 0, ov = 0;  // texel offsets
    float shade = 1;
    std::array<cv::Vec3d, 4> corners;  // culling polygon (disc: bounding square)
};

// Per-frame, per-primitive camera-space coefficients.
struct PrimFrame {
    float a0, a1, a2;      // w = 1/z = a . (rx, ry, 1)
    float b0, b1, b2, bo;  // u_m = z * (b . r) - bo
    float c0, c1, c2, co;  // v_m = z * (c . r) - co
    float abs_d;           // |n . P0| (distance of the plane from the camera)
};

// The camera for one frame: its pose in the world (FRD), and world points and directions in
// camera axes (x right, y down, z optical). The scene's primitives stay OpenCV vectors; they are
// converted here, per primitive, never per pixel.
struct CameraFrame {
    geom::Pose3 world_from_camera;
    geom::Mat3 camera_from_world;  // the rotation part of the inverse pose

    cv::Vec3d point(const cv::Vec3d& p_world) const {
        return geom::to_cv(camera_from_world *
                           (geom::from_cv(p_world) - world_from_camera.translation()));
    }
    cv::Vec3d direction(const cv::Vec3d& d_world) const {
        return geom::to_cv(camera_from_world * geom::from_cv(d_world));
    }
};

CameraFrame camera_frame(const Pose& p, CameraKind k) {
    const geom::Pose3 world_from_body = geom::world_from_body_pose(
        geom::world_point(p.x_m, p.y_m, p.z_m), p.roll_deg, p.pitch_deg, p.yaw_deg);
    const geom::Pose3 world_from_camera = geom::world_from_camera(world_from_body, k);
    return {world_from_camera, world_from_camera.linear().transpose()};
}

// The camera mirrored in the floor plane (FRD z = 0): its view is the floor's reflection. An
// improper rotation, which the visibility pass handles (it tests faces by world-frame dot
// products and takes each projected polygon's orientation from its signed area).
CameraFrame mirrored_in_floor(const CameraFrame& cf) {
    const geom::Mat3 m = geom::Vec3(1, 1, -1).asDiagonal();
    CameraFrame out = cf;
    out.world_from_camera.linear() = m * cf.world_from_camera.linear();
    out.world_from_camera.translation() = m * cf.world_from_camera.translation();
    out.camera_from_world = out.world_from_camera.linear().transpose();
    return out;
}

// log2 from the float's bits, mantissa linear: within 0.09 of the true value, plenty to pick a
// mip level, and far cheaper than std::log2 per pixel.
inline float fast_log2(float v) {
    const auto bits = std::bit_cast<std::int32_t>(v);
    return float(bits - (127 << 23)) * (1.0f / float(1 << 23));
}

inline int fast_floor(float v) {
    const int i = static_cast<int>(v);
    return i - (v < static_cast<float>(i) ? 1 : 0);
}

// Bilinear sample of a packed 0x00RRGGBB texture level (power-of-two side, wrapped).
inline std::uint32_t sample_bilinear(const std::uint32_t* d, int side, float u, float v) {
    const int mask = side - 1;
    const float fu = u - 0.5f, fv = v - 0.5f;
    const int iu = fast_floor(fu), iv = fast_floor(fv);
    const auto wu = static_cast<std::uint32_t>((fu - static_cast<float>(iu)) * 256.0f);
    const auto wv = static_cast<std::uint32_t>((fv - static_cast<float>(iv)) * 256.0f);
    const int x0 = iu & mask, x1 = (iu + 1) & mask, y0 = (iv & mask) * side,
              y1 = ((iv + 1) & mask) * side;
    const std::uint32_t c00 = d[y0 + x0], c01 = d[y0 + x1], c10 = d[y1 + x0], c11 = d[y1 + x1];
    auto lerp2 = [](std::uint32_t a, std::uint32_t b,
                    std::uint32_t w) {  // two 8-bit lanes at 0, 16
        return ((a * (256 - w) + b * w) >> 8) & 0x00FF00FFu;
    };
    const std::uint32_t rb = lerp2(lerp2(c00 & 0xFF00FF, c01 & 0xFF00FF, wu),
                                   lerp2(c10 & 0xFF00FF, c11 & 0xFF00FF, wu), wv);
    const std::uint32_t g = lerp2(lerp2((c00 >> 8) & 0xFF, (c01 >> 8) & 0xFF, wu),
                                  lerp2((c10 >> 8) & 0xFF, (c11 >> 8) & 0xFF, wu), wv);
    return rb | (g << 8);
}

}  // namespace

std::string to_string(RenderError e) {
    switch (e) {
        case RenderError::InvalidCalibration:
            return "invalid camera calibration";
        case RenderError::CalibrationNotInvertible:
            return "the distortion model cannot be inverted over the whole image";
    }
    return "unknown";
}

struct Renderer::Impl {
    CameraCalibration calib;
    CameraKind camera = CameraKind::Front;
    RenderOptions options;
    int W = 0, H = 0;
    std::vector<Prim> prims;
    std::vector<Texture> textures;
    std::vector<TextureSpec> texture_specs;

    // Per pixel, fixed: undistorted normalised ray (rx, ry, 1), inverse ray length, pixel
    // footprint in normalised units, vignetting gain (8.8 fixed point folded with shading later).
    std::vector<float> rx, ry, inv_r, foot2, vig;
    std::array<float, 16> level_scale{};
    // Blocks: normalised-coordinate bounds of the rays of each block, and per column / row.
    int bw = 0, bh = 0;
    std::vector<std::array<float, 4>> block_bounds;  // x0, x1, y0, y1
    std::vector<float> col_x0, col_x1, row_y0, row_y1;

    // Per frame, preallocated.
    std::vector<float> wbuf, ubuf, vbuf;
    std::vector<std::uint16_t> ids;
    std::vector<PrimFrame> frames;
    int drawn = 0;
    // Glossy floor: the floor's primitive, the mirror pass' buffers and image.
    int floor_prim = -1;
    // Moving boxes (set_movers): appended after the scene's own primitives.
    std::size_t static_prims = 0;
    Lighting lighting;
    std::vector<float> m_wbuf, m_ubuf, m_vbuf;
    std::vector<std::uint16_t> m_ids;
    cv::Mat mirror, mirror_tmp;

    int texture_index(const TextureSpec& spec) {
        for (std::size_t i = 0; i < texture_specs.size(); ++i)
            if (texture_specs[i] == spec) return int(i);
        texture_specs.push_back(spec);
        textures.push_back(make_texture(spec));
        return int(textures.size()) - 1;
    }

    float shade_for(const cv::Vec3d& n, const Lighting& l) const {
        // Light mostly from above (FRD z is down), a little from the front-right.
        const cv::Vec3d L = cv::normalize(cv::Vec3d(0.3, 0.2, -1.0));
        const double diffuse = 0.5 + 0.5 * n.dot(L);
        return float(l.gain * (l.ambient + (1.0 - l.ambient) * diffuse));
    }

    void add_rect(const cv::Vec3d& p0, const cv::Vec3d& U, const cv::Vec3d& V, const cv::Vec3d& n,
                  const TextureSpec& spec, double u_off_m, double v_off_m, const Lighting& l) {
        Prim p;
        p.p0 = p0;
        p.lu = cv::norm(U);
        p.lv = cv::norm(V);
        if (p.lu < 1e-6 || p.lv < 1e-6) return;
        p.eu = U / p.lu;
        p.ev = V / p.lv;
        p.n = n;
        p.tex = texture_index(spec);
        const Texture& t = textures[std::size_t(p.tex)];
        p.tu = p.tv = t.size / spec.scale_m;
        p.ou = u_off_m * p.tu;
        p.ov = v_off_m * p.tv;
        p.shade = shade_for(n, l);
        p.corners = {p0, p0 + U, p0 + U + V, p0 + V};
        prims.push_back(p);
    }

    // A vertical face seen from outside along -n: u to the right, v down.
    void add_vertical(const cv::Vec3d& centre, double width, double z_top_up, double z_bot_up,
                      const cv::Vec3d& n, const TextureSpec& spec, double u_off_m,
                      const Lighting& l) {
        const cv::Vec3d eu = cv::normalize(n.cross(kDown));
        const cv::Vec3d top_left = cv::Vec3d(centre[0], centre[1], -z_top_up) - eu * (width / 2);
        // v offset from the ceiling-side so textures line up between faces at the same height.
        add_rect(top_left, eu * width, kDown * (z_top_up - z_bot_up), n, spec, u_off_m, -z_top_up,
                 l);
    }

    void add_horizontal(const cv::Vec3d& corner, const cv::Vec3d& U, const cv::Vec3d& V, bool up,
                        const TextureSpec& spec, const Lighting& l) {
        add_rect(corner, U, V, up ? cv::Vec3d(0, 0, -1) : kDown, spec, corner[0], corner[1], l);
    }

    // A box obstacle: four vertical faces, a top and (raised) a bottom.
    void add_box(const Obstacle& o, const Lighting& L) {
        const double top = o.z_m + o.height_m, bot = o.z_m;
        const double c = std::cos(o.yaw_deg * kRadPerDeg), sn = std::sin(o.yaw_deg * kRadPerDeg);
        const cv::Vec3d ax(c, sn, 0), ay(-sn, c, 0);
        const cv::Vec3d ctr = frd(o.x_m, o.y_m, 0);
        const double hx = o.size_x_m / 2, hy = o.size_y_m / 2;
        // Around the box so u runs on across corners.
        const std::array<std::pair<cv::Vec3d, double>, 4> faces{
            {{-ax, o.size_y_m}, {ay, o.size_x_m}, {ax, o.size_y_m}, {-ay, o.size_x_m}}};
        double u = 0;
        for (const auto& [n, w] : faces) {
            const double half = (n == ax || n == -ax) ? hx : hy;
            add_vertical(ctr + n * half, w, top, bot, n, o.texture, u, L);
            u += w;
        }
        const cv::Vec3d corner = ctr - ax * hx - ay * hy;
        add_horizontal(corner + cv::Vec3d(0, 0, -top), ax * o.size_x_m, ay * o.size_y_m, true,
                       o.texture, L);
        if (bot > 0.01)
            add_horizontal(corner + cv::Vec3d(0, 0, -bot) + ay * o.size_y_m, ax * o.size_x_m,
                           -ay * o.size_y_m, false, o.texture, L);
    }

    void build(const Scene& s) {
        const Lighting& L = s.lighting;
        // Obstacles first: in the visibility pass they fill the depth buffer early.
        for (const Obstacle& o : s.obstacles) {
            const double top = o.z_m + o.height_m, bot = o.z_m;
            if (o.shape == ObstacleShape::Box) {
                add_box(o, L);
            } else {
                const int N = std::clamp(o.sides, 3, 64);
                const double width = 2 * o.radius_m * std::sin(std::numbers::pi / N);
                const double apothem = o.radius_m * std::cos(std::numbers::pi / N);
                for (int k = 0; k < N; ++k) {
                    const double a = (k + 0.5) * 2 * std::numbers::pi / N;
                    const cv::Vec3d n(std::cos(a), std::sin(a), 0);
                    add_vertical(frd(o.x_m, o.y_m, 0) + n * apothem, width, top, bot, n, o.texture,
                                 -k * width, L);
                }
                Prim p;
                p.disc = true;
                p.p0 = frd(o.x_m, o.y_m, top);
                p.eu = {1, 0, 0};
                p.ev = {0, 1, 0};
                p.n = {0, 0, -1};
                p.lu = p.lv = o.radius_m;
                p.tex = texture_index(o.texture);
                p.tu = p.tv = textures[std::size_t(p.tex)].size / o.texture.scale_m;
                p.shade = shade_for(p.n, L);
                const double r = o.radius_m;
                p.corners = {p.p0 + cv::Vec3d(-r, -r, 0), p.p0 + cv::Vec3d(r, -r, 0),
                             p.p0 + cv::Vec3d(r, r, 0), p.p0 + cv::Vec3d(-r, r, 0)};
                prims.push_back(p);
            }
        }
        // Room: floor, ceiling, four walls facing inwards.
        const Room& r = s.room;
        const double lx = r.x_max_m - r.x_min_m, ly = r.y_max_m - r.y_min_m;
        floor_prim = int(prims.size());
        add_horizontal(frd(r.x_min_m, r.y_min_m, 0), {lx, 0, 0}, {0, ly, 0}, true, r.floor, L);
        add_horizontal(frd(r.x_min_m, r.y_max_m, r.height_m), {lx, 0, 0}, {0, -ly, 0}, false,
                       r.ceiling, L);
        const double xm = (r.x_min_m + r.x_max_m) / 2, ym = (r.y_min_m + r.y_max_m) / 2;
        add_vertical(frd(r.x_max_m, ym, 0), ly, r.height_m, 0, {-1, 0, 0}, r.wall_front, 0, L);
        add_vertical(frd(r.x_min_m, ym, 0), ly, r.height_m, 0, {1, 0, 0}, r.wall_back, 0, L);
        add_vertical(frd(xm, r.y_min_m, 0), lx, r.height_m, 0, {0, 1, 0}, r.wall_left, 0, L);
        add_vertical(frd(xm, r.y_max_m, 0), lx, r.height_m, 0, {0, -1, 0}, r.wall_right, 0, L);
    }

    bool build_rays() {
        const std::size_t n = std::size_t(W) * std::size_t(H);
        rx.resize(n);
        ry.resize(n);
        inv_r.resize(n);
        foot2.resize(n);
        for (std::size_t l = 0; l < level_scale.size(); ++l) level_scale[l] = 1.0f / float(1 << l);
        vig.resize(n);
        // Invert the distortion at pixel corners, then take centres and footprints from them.
        const int CW = W + 1, CH = H + 1;
        std::vector<cv::Point2d> corner(std::size_t(CW) * std::size_t(CH));
        for (int y = 0; y < CH; ++y)
            for (int x = 0; x < CW; ++x) {
                auto u = undistort_pixel(calib, {x - 0.5, y - 0.5});
                if (!u) return false;
                corner[std::size_t(y) * std::size_t(CW) + std::size_t(x)] = *u;
            }
        const double diag = std::hypot(W / 2.0, H / 2.0);
        for (int y = 0; y < H; ++y)
            for (int x = 0; x < W; ++x) {
                const std::size_t i = std::size_t(y) * std::size_t(W) + std::size_t(x);
                auto c = undistort_pixel(calib, {double(x), double(y)});
                if (!c) return false;
                rx[i] = float(c->x);
                ry[i] = float(c->y);
                inv_r[i] = float(1.0 / std::sqrt(c->x * c->x + c->y * c->y + 1.0));
                const auto& a = corner[std::size_t(y) * std::size_t(CW) + std::size_t(x)];
                const auto& b = corner[std::size_t(y) * std::size_t(CW) + std::size_t(x) + 1];
                const auto& d = corner[std::size_t(y + 1) * std::size_t(CW) + std::size_t(x)];
                const cv::Point2d ex = b - a, ey = d - a;
                foot2[i] = float(std::abs(ex.x * ey.y - ex.y * ey.x));
                const double rr = std::hypot(x + 0.5 - W / 2.0, y + 0.5 - H / 2.0) / diag;
                vig[i] = float(1.0 - options_vignette * rr * rr);
            }
        bw = (W + kBlock - 1) / kBlock;
        bh = (H + kBlock - 1) / kBlock;
        block_bounds.assign(std::size_t(bw) * std::size_t(bh), {1e9f, -1e9f, 1e9f, -1e9f});
        col_x0.assign(std::size_t(bw), 1e9f);
        col_x1.assign(std::size_t(bw), -1e9f);
        row_y0.assign(std::size_t(bh), 1e9f);
        row_y1.assign(std::size_t(bh), -1e9f);
        for (int y = 0; y < CH; ++y)
            for (int x = 0; x < CW; ++x) {
                const auto& c = corner[std::size_t(y) * std::size_t(CW) + std::size_t(x)];
                // A corner bounds the (up to four) blocks it touches.
                for (int by = std::max(0, (y - 1) / kBlock); by <= std::min(bh - 1, y / kBlock);
                     ++by)
                    for (int bx = std::max(0, (x - 1) / kBlock); bx <= std::min(bw - 1, x / kBlock);
                         ++bx) {
                        auto& bb =
                            block_bounds[std::size_t(by) * std::size_t(bw) + std::size_t(bx)];
                        bb[0] = std::min(bb[0], float(c.x));
                        bb[1] = std::max(bb[1], float(c.x));
                        bb[2] = std::min(bb[2], float(c.y));
                        bb[3] = std::max(bb[3], float(c.y));
                    }
            }
        for (int by = 0; by < bh; ++by)
            for (int bx = 0; bx < bw; ++bx) {
                auto& bb = block_bounds[std::size_t(by) * std::size_t(bw) + std::size_t(bx)];
                // Margin for the curvature of block edges between sampled corners.
                const float mx = (bb[1] - bb[0]) * 0.02f + 1e-4f,
                            my = (bb[3] - bb[2]) * 0.02f + 1e-4f;
                bb[0] -= mx;
                bb[1] += mx;
                bb[2] -= my;
                bb[3] += my;
                col_x0[std::size_t(bx)] = std::min(col_x0[std::size_t(bx)], bb[0]);
                col_x1[std::size_t(bx)] = std::max(col_x1[std::size_t(bx)], bb[1]);
                row_y0[std::size_t(by)] = std::min(row_y0[std::size_t(by)], bb[2]);
                row_y1[std::size_t(by)] = std::max(row_y1[std::size_t(by)], bb[3]);
            }
        wbuf.resize(n);
        ubuf.resize(n);
        vbuf.resize(n);
        ids.resize(n);
        frames.resize(prims.size());
        return true;
    }
    double options_vignette = 0.35;

    // Visibility of one primitive: clip to z > near, project, cull blocks, cast pixel rays.
    void draw_prim(std::size_t pi, const CameraFrame& cf) {
        const Prim& p = prims[pi];
        const cv::Vec3d P0 = cf.point(p.p0);
        const cv::Vec3d n = cf.direction(p.n);
        const double d = n.dot(P0);
        if (d >= -1e-9) return;  // seen from behind (or edge-on)
        // Clip the culling polygon against the near plane.
        std::array<cv::Vec3d, 8> poly{}, clipped{};
        int np = 0, nc = 0;
        for (const auto& c : p.corners) poly[std::size_t(np++)] = cf.point(c);
        for (int k = 0; k < np; ++k) {
            const cv::Vec3d& a = poly[std::size_t(k)];
            const cv::Vec3d& b = poly[std::size_t((k + 1) % np)];
            const bool ia = a[2] > kNear, ib = b[2] > kNear;
            if (ia) clipped[std::size_t(nc++)] = a;
            if (ia != ib)
                clipped[std::size_t(nc++)] = a + (b - a) * ((kNear - a[2]) / (b[2] - a[2]));
        }
        if (nc < 3) return;
        std::array<cv::Point2f, 8> q{};
        float x0 = 1e30f, x1 = -1e30f, y0 = 1e30f, y1 = -1e30f;
        for (int k = 0; k < nc; ++k) {
            const auto& c = clipped[std::size_t(k)];
            q[std::size_t(k)] = {float(c[0] / c[2]), float(c[1] / c[2])};
            x0 = std::min(x0, q[std::size_t(k)].x);
            x1 = std::max(x1, q[std::size_t(k)].x);
            y0 = std::min(y0, q[std::size_t(k)].y);
            y1 = std::max(y1, q[std::size_t(k)].y);
        }
        int cx0 = bw, cx1 = -1, cy0 = bh, cy1 = -1;
        for (int bx = 0; bx < bw; ++bx)
            if (col_x1[std::size_t(bx)] >= x0 && col_x0[std::size_t(bx)] <= x1) {
                cx0 = std::min(cx0, bx);
                cx1 = bx;
            }
        for (int by = 0; by < bh; ++by)
            if (row_y1[std::size_t(by)] >= y0 && row_y0[std::size_t(by)] <= y1) {
                cy0 = std::min(cy0, by);
                cy1 = by;
            }
        if (cx1 < 0 || cy1 < 0) return;
        ++drawn;

        // Orientation of the projected polygon for the separating-axis test.
        double area = 0;
        for (int k = 0; k < nc; ++k) {
            const auto& a = q[std::size_t(k)];
            const auto& b = q[std::size_t((k + 1) % nc)];
            area += double(a.x) * double(b.y) - double(b.x) * double(a.y);
        }
        const float orient = area >= 0 ? 1.0f : -1.0f;

        PrimFrame& f = frames[pi];
        const cv::Vec3d a = n * (1.0 / d);
        const cv::Vec3d bu = cf.direction(p.eu), bv = cf.direction(p.ev);
        f = {float(a[0]),  float(a[1]),  float(a[2]),       float(bu[0]),
             float(bu[1]), float(bu[2]), float(bu.dot(P0)), float(bv[0]),
             float(bv[1]), float(bv[2]), float(bv.dot(P0)), float(-d)};
        const float eps = 1e-4f;
        const float lu = float(p.lu), lv = float(p.lv), r2 = float(p.lu * p.lu);
        const bool disc = p.disc;
        const auto id = static_cast<std::uint16_t>(pi);
        const PrimFrame pf = f;  // a local copy: the float stores below could alias `f`
        const float* const rx_p = rx.data();
        const float* const ry_p = ry.data();
        float* const w_p = wbuf.data();
        float* const u_p = ubuf.data();
        float* const v_p = vbuf.data();
        std::uint16_t* const id_p = ids.data();

        for (int by = cy0; by <= cy1; ++by)
            for (int bx = cx0; bx <= cx1; ++bx) {
                const auto& bb = block_bounds[std::size_t(by) * std::size_t(bw) + std::size_t(bx)];
                if (bb[1] < x0 || bb[0] > x1 || bb[3] < y0 || bb[2] > y1) continue;
                // Separating axis: an edge of the convex polygon with the whole block outside.
                bool outside = false;
                for (int k = 0; k < nc && !outside; ++k) {
                    const auto& e0 = q[std::size_t(k)];
                    const auto& e1 = q[std::size_t((k + 1) % nc)];
                    const float ex = (e1.x - e0.x) * orient, ey = (e1.y - e0.y) * orient;
                    // Inside is to the left: ex * (py - e0.y) - ey * (px - e0.x) >= 0.
                    const float px = ey > 0 ? bb[0] : bb[1];  // the block corner most inside
                    const float py = ex > 0 ? bb[3] : bb[2];
                    if (ex * (py - e0.y) - ey * (px - e0.x) < 0) outside = true;
                }
                if (outside) continue;
                const int px0 = bx * kBlock, px1 = std::min(W, px0 + kBlock);
                const int py0 = by * kBlock, py1 = std::min(H, py0 + kBlock);
                for (int y = py0; y < py1; ++y) {
                    const std::size_t row = std::size_t(y) * std::size_t(W);
                    for (int x = px0; x < px1; ++x) {
                        const std::size_t i = row + std::size_t(x);
                        const float X = rx_p[i], Y = ry_p[i];
                        const float w = pf.a0 * X + pf.a1 * Y + pf.a2;
                        if (!(w > w_p[i])) continue;
                        const float z = 1.0f / w;
                        const float um = z * (pf.b0 * X + pf.b1 * Y + pf.b2) - pf.bo;
                        const float vm = z * (pf.c0 * X + pf.c1 * Y + pf.c2) - pf.co;
                        if (disc) {
                            if (um * um + vm * vm > r2) continue;
                        } else if (um < -eps || vm < -eps || um > lu + eps || vm > lv + eps) {
                            continue;
                        }
                        w_p[i] = w;
                        u_p[i] = um;
                        v_p[i] = vm;
                        id_p[i] = id;
                    }
                }
            }
    }

    // The glossy floor: a second visibility and shading pass from the camera mirrored in the
    // floor, blurred, mixed into the floor's pixels. The main pass' buffers (inverse_depth())
    // are kept.
    void glossy_floor(const CameraFrame& cf, cv::Mat& out) {
        const std::size_t n = wbuf.size();
        m_wbuf.assign(n, 0.0f);
        m_ubuf.resize(n);
        m_vbuf.resize(n);
        m_ids.assign(n, kNoPrim);
        wbuf.swap(m_wbuf);
        ubuf.swap(m_ubuf);
        vbuf.swap(m_vbuf);
        ids.swap(m_ids);
        const int drawn_main = drawn;
        const CameraFrame mc = mirrored_in_floor(cf);
        for (std::size_t i = 0; i < prims.size(); ++i)
            if (int(i) != floor_prim) draw_prim(i, mc);
        mirror.create(H, W, CV_8UC3);
        shade(mirror);
        drawn = drawn_main;
        wbuf.swap(m_wbuf);
        ubuf.swap(m_ubuf);
        vbuf.swap(m_vbuf);
        ids.swap(m_ids);
        // A Gaussian of the angular sigma, approximated by three box blurs (sigma^2 = 3 (w^2 - 1)
        // / 12 for width w).
        const double sigma_px = options.floor_blur_deg * kRadPerDeg * calib.fx;
        const int w = int(std::lround(std::sqrt(4 * sigma_px * sigma_px + 1)));
        if (w >= 2)
            for (int k = 0; k < 3; ++k) {
                cv::blur(mirror, mirror_tmp, cv::Size(w, w), cv::Point(-1, -1), cv::BORDER_REFLECT);
                std::swap(mirror, mirror_tmp);
            }
        const int k256 = int(std::lround(std::clamp(options.floor_reflection, 0.0, 1.0) * 256));
        const auto floor_id = static_cast<std::uint16_t>(floor_prim);
        for (int y = 0; y < H; ++y) {
            std::uint8_t* o = out.ptr<std::uint8_t>(y);
            const std::uint8_t* r = mirror.ptr<std::uint8_t>(y);
            const std::uint16_t* id = ids.data() + std::size_t(y) * std::size_t(W);
            for (int x = 0; x < W; ++x) {
                if (id[x] != floor_id) continue;
                for (int c = 0; c < 3; ++c)
                    o[3 * x + c] = std::uint8_t(
                        (o[3 * x + c] * (256 - k256) + r[3 * x + c] * k256 + 128) >> 8);
            }
        }
    }

    void shade(cv::Mat& out) {
        const float bias = float(options.lod_bias);
        std::uint16_t last = kNoPrim;
        // Per-primitive values, reloaded only when the primitive changes along a row.
        float tu = 1, tv = 1, ou = 0, ov = 0, shade_k = 1, abs_d = 1, tu2 = 1;
        const Texture* t = nullptr;
        int max_level = 0;
        // Local pointers: the byte stores below may alias anything, members would be reloaded.
        const std::uint16_t* const id_p = ids.data();
        const float* const w_p = wbuf.data();
        const float* const u_p = ubuf.data();
        const float* const v_p = vbuf.data();
        const float* const ir_p = inv_r.data();
        const float* const f2_p = foot2.data();
        const float* const vig_p = vig.data();
        const std::array<float, 16> lscale = level_scale;
        const std::uint32_t* levels[16] = {};
        for (int y = 0; y < H; ++y) {
            auto* o = out.ptr<std::uint8_t>(y);
            const std::size_t row = std::size_t(y) * std::size_t(W);
            for (int x = 0; x < W; ++x) {
                const std::size_t i = row + std::size_t(x);
                const std::uint16_t id = id_p[i];
                if (id == kNoPrim) {
                    o[3 * x] = o[3 * x + 1] = o[3 * x + 2] = 128;
                    continue;
                }
                if (id != last) {
                    const Prim& p = prims[id];
                    t = &textures[std::size_t(p.tex)];
                    tu = float(p.tu);
                    tv = float(p.tv);
                    tu2 = tu * tu;
                    ou = float(p.ou);
                    ov = float(p.ov);
                    shade_k = p.shade * 256.0f;
                    abs_d = frames[id].abs_d;
                    max_level = std::min(15, int(t->levels.size()) - 1);
                    for (int l = 0; l <= max_level; ++l)
                        levels[l] = t->levels[std::size_t(l)].data();
                    last = id;
                }
                const float w = w_p[i];
                const float z = 1.0f / w;
                // Texel footprint: depth x pixel footprint, stretched on oblique surfaces (by the
                // geometric mean of the two axes' stretch: a compromise between blur and alias).
                const float cosi = std::max(0.02f, abs_d * w * ir_p[i]);
                const float rho2 = tu2 * z * z * f2_p[i] / cosi;
                const float lod = 0.5f * fast_log2(rho2) + bias;
                const int level = std::clamp(int(lod + 0.5f), 0, max_level);
                const float scale = lscale[std::size_t(level)];
                const float u = (u_p[i] * tu + ou) * scale;
                const float v = (v_p[i] * tv + ov) * scale;
                const std::uint32_t c = sample_bilinear(levels[level], t->size >> level, u, v);
                const auto gain = static_cast<std::uint32_t>(shade_k * vig_p[i]);
                o[3 * x] = std::uint8_t(std::min<std::uint32_t>(255, ((c & 0xFF) * gain) >> 8));
                o[3 * x + 1] =
                    std::uint8_t(std::min<std::uint32_t>(255, (((c >> 8) & 0xFF) * gain) >> 8));
                o[3 * x + 2] =
                    std::uint8_t(std::min<std::uint32_t>(255, (((c >> 16) & 0xFF) * gain) >> 8));
            }
        }
    }
};

Renderer::Renderer(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
Renderer::Renderer(Renderer&&) noexcept = default;
Renderer& Renderer::operator=(Renderer&&) noexcept = default;
Renderer::~Renderer() = default;

Expected<Renderer, RenderError> Renderer::create(const Scene& scene, const CameraCalibration& calib,
                                                 CameraKind camera, RenderOptions options) {
    if (!calib.valid() || calib.width > 4096 || calib.height > 4096)
        return Unexpected{RenderError::InvalidCalibration};
    auto impl = std::make_unique<Impl>();
    impl->calib = calib;
    impl->camera = camera;
    impl->options = options;
    impl->W = calib.width;
    impl->H = calib.height;
    impl->options_vignette = std::clamp(scene.lighting.vignette, 0.0, 0.95);
    impl->lighting = scene.lighting;
    impl->build(scene);
    impl->static_prims = impl->prims.size();
    if (impl->prims.size() >= kNoPrim) return Unexpected{RenderError::InvalidCalibration};
    if (!impl->build_rays()) return Unexpected{RenderError::CalibrationNotInvertible};
    return Renderer(std::move(impl));
}

void Renderer::render(const Pose& pose, cv::Mat& out) {
    Impl& m = *impl_;
    out.create(m.H, m.W, CV_8UC3);
    std::fill(m.wbuf.begin(), m.wbuf.end(), 0.0f);
    std::fill(m.ids.begin(), m.ids.end(), kNoPrim);
    const CameraFrame cf = camera_frame(pose, m.camera);
    m.drawn = 0;
    for (std::size_t i = 0; i < m.prims.size(); ++i) m.draw_prim(i, cf);
    m.shade(out);
    if (m.options.floor_reflection > 0 && m.floor_prim >= 0) m.glossy_floor(cf, out);
}

void Renderer::set_movers(std::span<const Obstacle> boxes) {
    Impl& m = *impl_;
    m.prims.resize(m.static_prims);
    for (const Obstacle& o : boxes) {
        if (m.prims.size() + 6 >= kNoPrim) break;
        if (o.shape == ObstacleShape::Box) m.add_box(o, m.lighting);
    }
    m.frames.resize(m.prims.size());
}

std::optional<cv::Point2d> Renderer::project(const Pose& pose, double x_m, double y_m,
                                             double z_m) const {
    const CameraFrame cf = camera_frame(pose, impl_->camera);
    const cv::Vec3d c = cf.point(frd(x_m, y_m, z_m));
    if (c[2] <= 1e-9) return std::nullopt;
    return distort_to_pixel(impl_->calib, {c[0] / c[2], c[1] / c[2]});
}

std::span<const float> Renderer::inverse_depth() const {
    return impl_->wbuf;
}

cv::Matx33d world_from_camera(const Pose& pose, CameraKind camera) {
    return geom::to_cv(camera_frame(pose, camera).world_from_camera.linear());
}

const CameraCalibration& Renderer::calibration() const {
    return impl_->calib;
}
CameraKind Renderer::camera() const {
    return impl_->camera;
}
RenderStats Renderer::stats() const {
    return {int(impl_->prims.size()), impl_->drawn, int(impl_->textures.size())};
}

}  // namespace gs::sim
