#include "drone/sim/scene.hpp"
#include "drone/sim/units.hpp"

#include "drone/sim/json_util.hpp"
#include "drone/sim/rng.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>

namespace gs::sim {
namespace {

TextureSpec read_texture(JsonReader& r, const nlohmann::json& j, const std::string& where,
                         const TextureSpec& def) {
    if (r.failed()) return def;
    if (!j.is_object()) {
        r.fail(AssetErrorKind::BadValue, where, "expected a texture object {\"kind\": ...}");
        return def;
    }
    TextureSpec t = def;
    const std::string kind = r.get_string(j, where, "kind");
    if (r.failed()) return def;
    const auto k = texture_kind_from_string(kind);
    if (!k) {
        std::string known;
        for (int i = 0; i <= int(TextureKind::Stripes); ++i)
            known += std::string(i ? ", " : "") + std::string(to_string(TextureKind(i)));
        r.fail(AssetErrorKind::BadValue, json_path(where, "kind"),
               "unknown texture kind \"" + kind + "\" (known: " + known + ")");
        return def;
    }
    t.kind = *k;
    const int seed = r.get_int(j, where, "seed", 1);
    if (seed < 0) r.fail(AssetErrorKind::BadValue, json_path(where, "seed"), "must be >= 0");
    t.seed = std::uint64_t(std::max(seed, 0));
    t.scale_m = r.get_number(j, where, "scale_m", def.scale_m);
    if (!r.failed() && !(t.scale_m > 0.01 && t.scale_m < 1000))
        r.fail(AssetErrorKind::BadValue, json_path(where, "scale_m"), "must be in (0.01, 1000)");
    auto colour = [&](const char* key) -> std::optional<cv::Vec3b> {
        if (!j.contains(key)) return std::nullopt;
        const auto c = r.get_numbers(j, where, key, 3, 3);
        if (r.failed()) return std::nullopt;
        for (double v : c)
            if (v < 0 || v > 255) {
                r.fail(AssetErrorKind::BadValue, json_path(where, key),
                       "components must be 0..255");
                return std::nullopt;
            }
        return cv::Vec3b(uchar(std::lround(c[0])), uchar(std::lround(c[1])),
                         uchar(std::lround(c[2])));
    };
    if (auto c = colour("color")) t.color_rgb = *c;
    if (auto c = colour("color2")) {
        t.color2_rgb = *c;
        t.has_color2 = true;
    }
    return t;
}

TextureSpec tex(TextureKind k, std::uint64_t seed, double scale, cv::Vec3b rgb) {
    TextureSpec t;
    t.kind = k;
    t.seed = seed;
    t.scale_m = scale;
    t.color_rgb = rgb;
    return t;
}

TextureSpec tex(TextureKind k, std::uint64_t seed, double scale, cv::Vec3b rgb, cv::Vec3b rgb2) {
    TextureSpec t = tex(k, seed, scale, rgb);
    t.color2_rgb = rgb2;
    t.has_color2 = true;
    return t;
}

bool valid_scenario(const std::string& s) {
    return s == "left" || s == "right" || s == "center" || s == "none";
}

// Footprint of a box as 4 (x, y) corners in the world frame.
std::array<cv::Point2d, 4> box_corners(const Obstacle& o) {
    const double c = std::cos(o.yaw_deg * kRadPerDeg), s = std::sin(o.yaw_deg * kRadPerDeg);
    const double hx = o.size_x_m / 2, hy = o.size_y_m / 2;
    std::array<cv::Point2d, 4> out;
    const double sx[4] = {-1, 1, 1, -1}, sy[4] = {-1, -1, 1, 1};
    for (int i = 0; i < 4; ++i) {
        const double lx = sx[i] * hx, ly = sy[i] * hy;
        out[std::size_t(i)] = {o.x_m + c * lx - s * ly, o.y_m + s * lx + c * ly};
    }
    return out;
}

// (along, lateral) of a world point relative to a line from (x, y) heading h.
cv::Point2d to_flight(double px, double py, double x, double y, double h_deg) {
    const double c = std::cos(h_deg * kRadPerDeg), s = std::sin(h_deg * kRadPerDeg);
    const double dx = px - x, dy = py - y;
    return {dx * c + dy * s, -dx * s + dy * c};
}

}  // namespace

Expected<Scene, AssetError> load_scene(const std::string& path) {
    GS_TRY_ASSIGN(auto doc, read_json_file(path));
    const nlohmann::json& j = doc;
    JsonReader r(path);
    Scene s;
    s.source_file = path;
    s.name = r.get_string(j, "", "name", "");
    s.description = r.get_string(j, "", "description", "");

    // Room.
    if (const auto* room = r.get_object(j, "", "room", true)) {
        const auto xs = r.get_numbers(*room, "room", "x_m", 2, 2);
        const auto ys = r.get_numbers(*room, "room", "y_m", 2, 2);
        s.room.height_m = r.get_number(*room, "room", "height_m");
        if (!r.failed()) {
            s.room.x_min_m = xs[0];
            s.room.x_max_m = xs[1];
            s.room.y_min_m = ys[0];
            s.room.y_max_m = ys[1];
            if (!(xs[1] - xs[0] > 0.5 && xs[1] - xs[0] < 1000))
                r.fail(AssetErrorKind::BadValue, "room.x_m",
                       "need [min, max] with max - min in (0.5, 1000)");
            else if (!(ys[1] - ys[0] > 0.5 && ys[1] - ys[0] < 1000))
                r.fail(AssetErrorKind::BadValue, "room.y_m",
                       "need [min, max] with max - min in (0.5, 1000)");
            else if (!(s.room.height_m > 0.5 && s.room.height_m < 100))
                r.fail(AssetErrorKind::BadValue, "room.height_m", "must be in (0.5, 100)");
        }
        const TextureSpec floor_def = tex(TextureKind::Tiles, 1, 2.4, {170, 165, 150});
        const TextureSpec ceil_def = tex(TextureKind::Ceiling, 2, 2.4, {225, 225, 220});
        const TextureSpec wall_def = tex(TextureKind::Posters, 3, 4.0, {200, 195, 180});
        s.room.floor = room->contains("floor")
                           ? read_texture(r, (*room)["floor"], "room.floor", floor_def)
                           : floor_def;
        s.room.ceiling = room->contains("ceiling")
                             ? read_texture(r, (*room)["ceiling"], "room.ceiling", ceil_def)
                             : ceil_def;
        const TextureSpec walls = room->contains("walls")
                                      ? read_texture(r, (*room)["walls"], "room.walls", wall_def)
                                      : wall_def;
        auto wall = [&](const char* key, std::uint64_t salt) {
            if (room->contains(key))
                return read_texture(r, (*room)[key], std::string("room.") + key, walls);
            TextureSpec t = walls;
            t.seed = mix_seed(walls.seed, salt);
            return t;
        };
        s.room.wall_front = wall("wall_front", 1);
        s.room.wall_back = wall("wall_back", 2);
        s.room.wall_left = wall("wall_left", 3);
        s.room.wall_right = wall("wall_right", 4);
    }

    // Lighting.
    if (const auto* l = r.get_object(j, "", "lighting", false)) {
        s.lighting.gain = r.get_number(*l, "lighting", "gain", 1.0);
        s.lighting.ambient = r.get_number(*l, "lighting", "ambient", 0.6);
        s.lighting.vignette = r.get_number(*l, "lighting", "vignette", 0.35);
        if (!r.failed() && !(s.lighting.gain > 0 && s.lighting.gain < 10))
            r.fail(AssetErrorKind::BadValue, "lighting.gain", "must be in (0, 10)");
        if (!r.failed() && !(s.lighting.ambient >= 0 && s.lighting.ambient <= 1))
            r.fail(AssetErrorKind::BadValue, "lighting.ambient", "must be in [0, 1]");
        if (!r.failed() && !(s.lighting.vignette >= 0 && s.lighting.vignette < 1))
            r.fail(AssetErrorKind::BadValue, "lighting.vignette", "must be in [0, 1)");
    }

    // Obstacles.
    if (const auto* obs = r.get_array(j, "", "obstacles", false)) {
        for (std::size_t i = 0; i < obs->size() && !r.failed(); ++i) {
            const std::string where = "obstacles[" + std::to_string(i) + "]";
            const auto& o = (*obs)[i];
            if (!o.is_object()) {
                r.fail(AssetErrorKind::BadValue, where, "expected an object");
                break;
            }
            Obstacle ob;
            ob.id = r.get_string(o, where, "id", "");
            const std::string type = r.get_string(o, where, "type");
            const auto c = r.get_numbers(o, where, "center_m", 2, 2);
            if (r.failed()) break;
            ob.x_m = c[0];
            ob.y_m = c[1];
            ob.z_m = r.get_number(o, where, "z_m", 0.0);
            ob.height_m = r.get_number(o, where, "height_m", s.room.height_m - ob.z_m);
            ob.clutter = r.get_bool(o, where, "clutter", false);
            if (type == "box") {
                ob.shape = ObstacleShape::Box;
                const auto sz = r.get_numbers(o, where, "size_m", 2, 2);
                if (r.failed()) break;
                ob.size_x_m = sz[0];
                ob.size_y_m = sz[1];
                ob.yaw_deg = r.get_number(o, where, "yaw_deg", 0.0);
                if (!(sz[0] > 0.005 && sz[1] > 0.005 && sz[0] < 1000 && sz[1] < 1000))
                    r.fail(AssetErrorKind::BadValue, where + ".size_m",
                           "sizes must be in (0.005, 1000)");
            } else if (type == "cylinder") {
                ob.shape = ObstacleShape::Cylinder;
                ob.radius_m = r.get_number(o, where, "radius_m");
                ob.sides = r.get_int(o, where, "sides", 16);
                if (!r.failed() && !(ob.radius_m > 0.005 && ob.radius_m < 500))
                    r.fail(AssetErrorKind::BadValue, where + ".radius_m",
                           "must be in (0.005, 500)");
                if (!r.failed() && (ob.sides < 3 || ob.sides > 64))
                    r.fail(AssetErrorKind::BadValue, where + ".sides", "must be 3..64");
            } else if (!r.failed()) {
                r.fail(AssetErrorKind::BadValue, where + ".type",
                       "unknown obstacle type \"" + type + "\" (known: box, cylinder)");
            }
            if (!r.failed() && !(ob.height_m > 0.005 && ob.height_m < 1000))
                r.fail(AssetErrorKind::BadValue, where + ".height_m", "must be in (0.005, 1000)");
            const TextureSpec def = tex(TextureKind::Tape, 10 + i, 1.0, {25, 25, 28});
            ob.texture = o.contains("texture")
                             ? read_texture(r, o["texture"], where + ".texture", def)
                             : def;
            s.obstacles.push_back(ob);
        }
    }

    // Start pose.
    if (const auto* st = r.get_object(j, "", "start", true)) {
        s.start.x_m = r.get_number(*st, "start", "x_m");
        s.start.y_m = r.get_number(*st, "start", "y_m");
        s.start.z_m = r.get_number(*st, "start", "z_m", 1.0);
        s.start.yaw_deg = r.get_number(*st, "start", "yaw_deg", 0.0);
        if (!r.failed() && (s.start.x_m <= s.room.x_min_m || s.start.x_m >= s.room.x_max_m ||
                            s.start.y_m <= s.room.y_min_m || s.start.y_m >= s.room.y_max_m ||
                            s.start.z_m <= 0 || s.start.z_m >= s.room.height_m))
            r.fail(AssetErrorKind::BadValue, "start", "start pose is outside the room");
    }

    s.scenario = r.get_string(j, "", "scenario", "none");
    if (!r.failed() && !valid_scenario(s.scenario))
        r.fail(AssetErrorKind::BadValue, "scenario", "must be left, right, center or none");
    s.target_id = r.get_string(j, "", "target", "");
    if (!r.failed() && !s.target_id.empty() && !find_obstacle(s, s.target_id))
        r.fail(AssetErrorKind::BadValue, "target", "no obstacle has id \"" + s.target_id + "\"");
    if (!r.failed() && s.scenario != "none" && s.target_id.empty())
        r.fail(AssetErrorKind::MissingKey, "target", "required when scenario is not \"none\"");

    if (const auto* ap = r.get_array(j, "", "autopilot", false)) {
        for (std::size_t i = 0; i < ap->size() && !r.failed(); ++i) {
            const std::string where = "autopilot[" + std::to_string(i) + "]";
            const auto& a = (*ap)[i];
            AutopilotStep step;
            step.action = r.get_string(a, where, "action");
            step.duration_s = r.get_number(a, where, "duration_s", 0.0);
            step.vx_mps = r.get_number(a, where, "vx_mps", 0.0);
            step.vy_mps = r.get_number(a, where, "vy_mps", 0.0);
            step.vz_mps = r.get_number(a, where, "vz_mps", 0.0);
            step.yaw_rate_dps = r.get_number(a, where, "yaw_rate_dps", 0.0);
            if (r.failed()) break;
            if (step.action != "takeoff" && step.action != "hover" && step.action != "move" &&
                step.action != "land")
                r.fail(
                    AssetErrorKind::BadValue, where + ".action",
                    "unknown action \"" + step.action + "\" (known: takeoff, hover, move, land)");
            else if (!(step.duration_s >= 0 && step.duration_s < 3600))
                r.fail(AssetErrorKind::BadValue, where + ".duration_s", "must be in [0, 3600)");
            s.autopilot.push_back(step);
        }
    }
    if (r.failed()) return Unexpected{r.error()};
    return s;
}

double footprint_distance(const Obstacle& o, double x_m, double y_m) {
    const double dx = x_m - o.x_m, dy = y_m - o.y_m;
    if (o.shape == ObstacleShape::Cylinder) return std::max(0.0, std::hypot(dx, dy) - o.radius_m);
    // Into the box's own axes (box_corners turns local (lx, ly) by +yaw).
    const double c = std::cos(o.yaw_deg * kRadPerDeg), s = std::sin(o.yaw_deg * kRadPerDeg);
    const double lx = c * dx + s * dy, ly = -s * dx + c * dy;
    const double ex = std::max(0.0, std::abs(lx) - o.size_x_m / 2);
    const double ey = std::max(0.0, std::abs(ly) - o.size_y_m / 2);
    return std::hypot(ex, ey);
}

std::optional<std::size_t> find_obstacle(const Scene& s, const std::string& id) {
    for (std::size_t i = 0; i < s.obstacles.size(); ++i)
        if (!id.empty() && s.obstacles[i].id == id) return i;
    return std::nullopt;
}

ObstacleHit obstacle_relative(const Scene& s, std::size_t index, double x_m, double y_m,
                              double heading_deg) {
    const Obstacle& o = s.obstacles.at(index);
    ObstacleHit h;
    h.index = index;
    const cv::Point2d c = to_flight(o.x_m, o.y_m, x_m, y_m, heading_deg);
    h.lateral_m = c.y;
    if (o.shape == ObstacleShape::Cylinder) {
        h.distance_m = c.x - o.radius_m;
    } else {
        double m = std::numeric_limits<double>::infinity();
        for (const auto& p : box_corners(o))
            m = std::min(m, to_flight(p.x, p.y, x_m, y_m, heading_deg).x);
        h.distance_m = m;
    }
    return h;
}

std::optional<ObstacleHit> obstacle_ahead(const Scene& s, double x_m, double y_m,
                                          double heading_deg, double half_width_m,
                                          double max_range_m) {
    std::optional<ObstacleHit> best;
    for (std::size_t i = 0; i < s.obstacles.size(); ++i) {
        const Obstacle& o = s.obstacles[i];
        const cv::Point2d c = to_flight(o.x_m, o.y_m, x_m, y_m, heading_deg);
        double near = std::numeric_limits<double>::infinity();
        if (o.shape == ObstacleShape::Cylinder) {
            if (c.y - o.radius_m > half_width_m || c.y + o.radius_m < -half_width_m) continue;
            const double le = std::clamp(c.y, -half_width_m, half_width_m);
            const double dl = le - c.y;
            near = c.x - std::sqrt(std::max(0.0, o.radius_m * o.radius_m - dl * dl));
        } else {
            // Clip the footprint polygon to the band |lateral| <= half_width, take the least along.
            std::vector<cv::Point2d> poly;
            for (const auto& p : box_corners(o))
                poly.push_back(to_flight(p.x, p.y, x_m, y_m, heading_deg));
            for (int side = -1; side <= 1; side += 2) {
                std::vector<cv::Point2d> out;
                const double lim = side * half_width_m;
                auto inside = [&](const cv::Point2d& p) {
                    return side < 0 ? p.y >= lim : p.y <= lim;
                };
                for (std::size_t k = 0; k < poly.size(); ++k) {
                    const cv::Point2d a = poly[k], b = poly[(k + 1) % poly.size()];
                    if (inside(a)) out.push_back(a);
                    if (inside(a) != inside(b)) {
                        const double t = (lim - a.y) / (b.y - a.y);
                        out.push_back(a + (b - a) * t);
                    }
                }
                poly = std::move(out);
            }
            if (poly.empty()) continue;
            for (const auto& p : poly) near = std::min(near, p.x);
        }
        if (near < 0 || near > max_range_m) continue;
        if (!best || near < best->distance_m) best = ObstacleHit{i, near, c.y};
    }
    return best;
}

std::optional<double> ray_distance(const Scene& s, double ox, double oy, double oz, double dx,
                                   double dy, double dz) {
    const double len = std::sqrt(dx * dx + dy * dy + dz * dz);
    if (!(len > 0)) return std::nullopt;
    dx /= len;
    dy /= len;
    dz /= len;
    const Room& r = s.room;
    if (ox <= r.x_min_m || ox >= r.x_max_m || oy <= r.y_min_m || oy >= r.y_max_m || oz <= 0 ||
        oz >= r.height_m)
        return std::nullopt;
    double best = std::numeric_limits<double>::infinity();
    auto exit_t = [&](double o, double d, double lo, double hi) {
        if (d > 0) best = std::min(best, (hi - o) / d);
        if (d < 0) best = std::min(best, (lo - o) / d);
    };
    exit_t(ox, dx, r.x_min_m, r.x_max_m);
    exit_t(oy, dy, r.y_min_m, r.y_max_m);
    exit_t(oz, dz, 0.0, r.height_m);
    for (const Obstacle& o : s.obstacles) {
        // Into the obstacle's local frame (yaw about z), then slab / circle tests.
        const double c = std::cos(o.yaw_deg * kRadPerDeg), sn = std::sin(o.yaw_deg * kRadPerDeg);
        const double px = ox - o.x_m, py = oy - o.y_m;
        double lx = c * px + sn * py, ly = -sn * px + c * py, lz = oz - o.z_m;
        double ux = c * dx + sn * dy, uy = -sn * dx + c * dy, uz = dz;
        double t0 = 0, t1 = std::numeric_limits<double>::infinity();
        auto slab = [&](double p, double u, double lo, double hi) {
            if (std::abs(u) < 1e-15) {
                if (p < lo || p > hi) t1 = -1;
                return;
            }
            double a = (lo - p) / u, b = (hi - p) / u;
            if (a > b) std::swap(a, b);
            t0 = std::max(t0, a);
            t1 = std::min(t1, b);
        };
        slab(lz, uz, 0.0, o.height_m);
        if (o.shape == ObstacleShape::Box) {
            slab(lx, ux, -o.size_x_m / 2, o.size_x_m / 2);
            slab(ly, uy, -o.size_y_m / 2, o.size_y_m / 2);
        } else {
            lx = px;
            ly = py;
            ux = dx;
            uy = dy;
            const double a = ux * ux + uy * uy, b = 2 * (lx * ux + ly * uy),
                         cc = lx * lx + ly * ly - o.radius_m * o.radius_m;
            if (a < 1e-15) {
                if (cc > 0) t1 = -1;
            } else {
                const double disc = b * b - 4 * a * cc;
                if (disc < 0) {
                    t1 = -1;
                } else {
                    const double sq = std::sqrt(disc);
                    t0 = std::max(t0, (-b - sq) / (2 * a));
                    t1 = std::min(t1, (-b + sq) / (2 * a));
                }
            }
        }
        if (t0 <= t1 && t1 >= 0) best = std::min(best, t0);
    }
    return best;
}

// ---- Generator ---------------------------------------------------------------------------

namespace {

cv::Vec3b random_colour(Rng& rng, int lo, int hi) {
    return {uchar(rng.range(lo, hi)), uchar(rng.range(lo, hi)), uchar(rng.range(lo, hi))};
}

cv::Vec3b pick(Rng& rng, std::initializer_list<cv::Vec3b> options) {
    const int i = rng.range(0, int(options.size()) - 1);
    return *(options.begin() + i);
}

TextureSpec random_wall(Rng& rng, double richness) {
    const std::uint64_t seed = rng.next() & 0xffffff;
    if (rng.chance((1.0 - richness) * 0.6))
        return tex(TextureKind::Plain, seed, 3.0,
                   pick(rng, {{225, 220, 205}, {200, 210, 215}, {235, 230, 220}}));
    switch (rng.range(0, 4)) {
        case 0:
            return tex(TextureKind::Bricks, seed, rng.uniform(1.6, 2.4),
                       pick(rng, {{150, 70, 50}, {170, 90, 60}, {120, 60, 45}}));
        case 1:
            return tex(TextureKind::Concrete, seed, rng.uniform(2.0, 4.0),
                       random_colour(rng, 140, 190));
        case 2:
            return tex(TextureKind::Posters, seed, rng.uniform(3.0, 5.0),
                       pick(rng, {{215, 210, 195}, {190, 205, 210}, {230, 220, 190}}),
                       random_colour(rng, 40, 220));
        case 3:
            return tex(TextureKind::Wood, seed, rng.uniform(1.5, 2.5),
                       pick(rng, {{150, 105, 65}, {180, 140, 90}}));
        default:
            return tex(TextureKind::Noise, seed, rng.uniform(1.0, 3.0),
                       random_colour(rng, 150, 220), random_colour(rng, 40, 110));
    }
}

TextureSpec random_floor(Rng& rng, double richness) {
    const std::uint64_t seed = rng.next() & 0xffffff;
    if (rng.chance((1.0 - richness) * 0.5))
        return tex(TextureKind::Concrete, seed, 4.0, random_colour(rng, 120, 160));
    switch (rng.range(0, 3)) {
        case 0:
            return tex(TextureKind::Tiles, seed, rng.uniform(1.6, 2.8),
                       random_colour(rng, 140, 210));
        case 1:
            return tex(TextureKind::Wood, seed, rng.uniform(1.5, 2.5),
                       pick(rng, {{160, 115, 70}, {120, 85, 55}}));
        case 2:
            return tex(TextureKind::Checker, seed, rng.uniform(2.0, 4.0),
                       random_colour(rng, 170, 220), random_colour(rng, 50, 100));
        default:
            return tex(TextureKind::Concrete, seed, rng.uniform(2.0, 4.0),
                       random_colour(rng, 110, 170));
    }
}

TextureSpec random_obstacle_texture(Rng& rng, double richness) {
    const std::uint64_t seed = rng.next() & 0xffffff;
    if (rng.chance((1.0 - richness) * 0.4))
        return tex(TextureKind::Concrete, seed, 1.5, random_colour(rng, 130, 180));
    switch (rng.range(0, 5)) {
        case 0:
            return tex(TextureKind::Tape, seed, rng.uniform(0.8, 1.2), {25, 25, 28});
        case 1:
            return tex(TextureKind::Paper, seed, rng.uniform(1.2, 2.0),
                       random_colour(rng, 140, 180));
        case 2:
            return tex(TextureKind::Bricks, seed, rng.uniform(1.2, 2.0),
                       pick(rng, {{150, 70, 50}, {170, 90, 60}}));
        case 3:
            return tex(TextureKind::Posters, seed, rng.uniform(1.5, 2.5),
                       random_colour(rng, 150, 220), random_colour(rng, 40, 220));
        case 4:
            return tex(TextureKind::Stripes, seed, rng.uniform(0.6, 1.2), {230, 190, 30});
        default:
            return tex(TextureKind::Noise, seed, rng.uniform(0.6, 1.5),
                       random_colour(rng, 150, 230), random_colour(rng, 20, 90));
    }
}

}  // namespace

Scene generate_scene(const GeneratorParams& p, std::uint64_t seed) {
    Rng rng(mix_seed(seed, 0x5ce9e));
    Scene s;
    s.name = "generated-" + p.scenario + "-" + std::to_string(seed);
    s.description = "seeded random indoor scene";
    s.scenario = valid_scenario(p.scenario) ? p.scenario : "none";
    const double richness = std::clamp(p.texture_richness, 0.0, 1.0);

    Room& room = s.room;
    room.x_min_m = -rng.uniform(1.5, 4.0);
    room.x_max_m = p.start_distance_m + rng.uniform(6.0, 16.0);
    const double y_centre = rng.uniform(-1.5, 1.5);
    const double half_w = rng.uniform(3.5, 8.0);
    room.y_min_m = y_centre - half_w;
    room.y_max_m = y_centre + half_w;
    room.height_m = rng.uniform(2.7, 4.5);
    room.floor = random_floor(rng, richness);
    room.ceiling = tex(TextureKind::Ceiling, rng.next() & 0xffff, rng.uniform(2.0, 3.0),
                       random_colour(rng, 205, 235));
    room.wall_front = random_wall(rng, richness);
    room.wall_back = random_wall(rng, richness);
    room.wall_left = random_wall(rng, richness);
    room.wall_right = random_wall(rng, richness);

    s.lighting.gain = p.light_gain * rng.uniform(0.8, 1.2);
    s.lighting.ambient = rng.uniform(0.5, 0.7);
    s.lighting.vignette = rng.uniform(0.2, 0.45);

    s.start = Pose{0.0, 0.0, std::clamp(p.start_height_m, 0.3, room.height_m - 0.3), 0, 0, 0};

    // The target.
    double flight_m = p.start_distance_m + 3.0;
    if (s.scenario != "none") {
        Obstacle t;
        t.id = "target";
        t.texture = random_obstacle_texture(rng, richness);
        const bool cylinder = rng.chance(0.4);
        const double size = rng.uniform(0.3, 0.7);
        const bool to_ceiling = rng.chance(0.7);
        t.height_m = to_ceiling ? room.height_m : std::min(room.height_m, rng.uniform(2.0, 2.6));
        double half_depth = size / 2;
        if (cylinder) {
            t.shape = ObstacleShape::Cylinder;
            t.radius_m = size / 2;
            t.sides = 20;
        } else {
            t.shape = ObstacleShape::Box;
            t.size_x_m = size;
            t.size_y_m = size * rng.uniform(0.8, 1.25);
            half_depth = t.size_x_m / 2;
        }
        const double lateral = s.scenario == "left"    ? -p.lateral_offset_m
                               : s.scenario == "right" ? p.lateral_offset_m
                                                       : rng.uniform(-0.08, 0.08);
        t.x_m = s.start.x_m + p.start_distance_m + half_depth;
        t.y_m = s.start.y_m + lateral;
        s.obstacles.push_back(t);
        s.target_id = t.id;
        flight_m = s.scenario == "center" ? p.start_distance_m - 0.5 : p.start_distance_m + 2.0;
    }

    // Clutter: keeps out of the corridor |y| < 1.6 m around the flight line.
    const double corridor = 1.6;
    const double area = (room.x_max_m - room.x_min_m) * (room.y_max_m - room.y_min_m);
    const int n = int(std::lround(std::clamp(p.clutter_density, 0.0, 2.0) * area / 6.0));
    for (int i = 0; i < n; ++i) {
        const double x = rng.uniform(room.x_min_m + 0.5, room.x_max_m - 0.5);
        double y = 0;
        const double free_left = (s.start.y_m - corridor) - (room.y_min_m + 0.4);
        const double free_right = (room.y_max_m - 0.4) - (s.start.y_m + corridor);
        if (free_left <= 0 && free_right <= 0) break;
        if (free_right <= 0 || (free_left > 0 && rng.chance(free_left / (free_left + free_right))))
            y = rng.uniform(room.y_min_m + 0.4, s.start.y_m - corridor);
        else
            y = rng.uniform(s.start.y_m + corridor, room.y_max_m - 0.4);
        const double d_edge = std::min(std::abs(y - (s.start.y_m - corridor)),
                                       std::abs(y - (s.start.y_m + corridor)));
        Obstacle o;
        o.clutter = true;
        o.x_m = x;
        o.y_m = y;
        const int kind = rng.range(0, 9);
        if (kind <= 3) {  // cardboard box stack
            const double w = rng.uniform(0.3, 0.8);
            int levels = rng.range(1, 3);
            double z = 0;
            const double yaw = rng.uniform(-30, 30);
            for (int l = 0; l < levels; ++l) {
                Obstacle b = o;
                b.shape = ObstacleShape::Box;
                b.size_x_m = w * rng.uniform(0.8, 1.0);
                b.size_y_m = w * rng.uniform(0.7, 1.2);
                b.height_m = w * rng.uniform(0.5, 0.9);
                b.z_m = z;
                b.yaw_deg = yaw + rng.uniform(-8, 8);
                b.texture =
                    tex(TextureKind::Cardboard, rng.next() & 0xffffff, rng.uniform(0.6, 1.0),
                        pick(rng, {{175, 135, 90}, {160, 120, 80}, {190, 150, 100}}));
                z += b.height_m;
                if (z > room.height_m) break;
                s.obstacles.push_back(b);
            }
        } else if (kind <= 5) {  // bin / barrel
            o.shape = ObstacleShape::Cylinder;
            o.radius_m = rng.uniform(0.15, 0.35);
            o.height_m = rng.uniform(0.5, 1.1);
            o.sides = 14;
            o.texture = random_obstacle_texture(rng, richness);
            s.obstacles.push_back(o);
        } else if (kind <= 7) {  // table: top and four legs
            const double tw = rng.uniform(0.8, 1.6), td = rng.uniform(0.6, 0.9),
                         th = rng.uniform(0.7, 0.78);
            const TextureSpec wood = tex(TextureKind::Wood, rng.next() & 0xffffff, 1.2,
                                         pick(rng, {{150, 105, 65}, {200, 190, 170}}));
            const double maxw = std::max(0.3, 2 * d_edge);
            Obstacle top = o;
            top.shape = ObstacleShape::Box;
            top.size_x_m = tw;
            top.size_y_m = std::min(td, maxw);
            top.height_m = 0.04;
            top.z_m = th - 0.04;
            top.texture = wood;
            s.obstacles.push_back(top);
            for (int k = 0; k < 4; ++k) {
                Obstacle leg = o;
                leg.shape = ObstacleShape::Box;
                leg.size_x_m = leg.size_y_m = 0.05;
                leg.x_m = o.x_m + ((k & 1) ? 1 : -1) * (top.size_x_m / 2 - 0.05);
                leg.y_m = o.y_m + ((k & 2) ? 1 : -1) * (top.size_y_m / 2 - 0.05);
                leg.height_m = th - 0.04;
                leg.texture = tex(TextureKind::Plain, 7, 1.0, {60, 60, 65});
                s.obstacles.push_back(leg);
            }
        } else {  // another pillar, floor to ceiling, well off the path
            if (d_edge < 0.8) continue;
            o.shape = rng.chance(0.5) ? ObstacleShape::Box : ObstacleShape::Cylinder;
            o.size_x_m = o.size_y_m = rng.uniform(0.3, 0.6);
            o.radius_m = o.size_x_m / 2;
            o.sides = 16;
            o.height_m = room.height_m;
            o.texture = random_obstacle_texture(rng, richness);
            s.obstacles.push_back(o);
        }
    }

    s.autopilot = {AutopilotStep{"move", flight_m / 1.0, 1.0, 0, 0, 0}};
    return s;
}

}  // namespace gs::sim
