#include "drone/sim/collision.hpp"

#include "drone/sim/scene.hpp"
#include "drone/sim/units.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace gs::sim {
namespace {

struct V2 {
    double x = 0, y = 0;
};
V2 operator-(V2 a, V2 b) {
    return {a.x - b.x, a.y - b.y};
}
V2 operator+(V2 a, V2 b) {
    return {a.x + b.x, a.y + b.y};
}
V2 operator*(double k, V2 a) {
    return {k * a.x, k * a.y};
}
double dot(V2 a, V2 b) {
    return a.x * b.x + a.y * b.y;
}

// A yawed rectangle: centre, unit axes (u along its local x, v along its local y), half sizes.
struct Rect {
    V2 c, u, v;
    double hu = 0, hv = 0;
    double radius_on(V2 axis) const {
        return hu * std::abs(dot(u, axis)) + hv * std::abs(dot(v, axis));
    }
    std::array<V2, 4> corners() const {
        return {c + hu * u + hv * v, c + hu * u - hv * v, c - hu * u - hv * v, c - hu * u + hv * v};
    }
};

Rect make_rect(double x, double y, double hu, double hv, double yaw_rad) {
    const double c = std::cos(yaw_rad), s = std::sin(yaw_rad);
    return {{x, y}, {c, s}, {-s, c}, hu, hv};  // local x = (c, s), local y = (-s, c) (scene.cpp)
}

// Horizontal penetration of `body` into `r` (separating-axis test): the depth and the unit
// normal out of `r` towards the body. nullopt when they do not overlap.
std::optional<std::pair<double, V2>> rect_rect(const Rect& body, const Rect& r) {
    double best = std::numeric_limits<double>::infinity();
    V2 normal;
    const V2 d = body.c - r.c;
    for (V2 axis : {body.u, body.v, r.u, r.v}) {
        const double dist = dot(d, axis);
        const double overlap = body.radius_on(axis) + r.radius_on(axis) - std::abs(dist);
        if (overlap <= 0) return std::nullopt;
        if (overlap < best) {
            best = overlap;
            normal = dist >= 0 ? axis : -1.0 * axis;
        }
    }
    return std::make_pair(best, normal);
}

// The point of `r` nearest to p.
V2 closest_in(const Rect& r, V2 p) {
    const V2 d = p - r.c;
    const double a = std::clamp(dot(d, r.u), -r.hu, r.hu);
    const double b = std::clamp(dot(d, r.v), -r.hv, r.hv);
    return r.c + a * r.u + b * r.v;
}

// Penetration of `body` into a circle.
std::optional<std::pair<double, V2>> rect_circle(const Rect& body, V2 centre, double radius) {
    const V2 q = closest_in(body, centre);
    const V2 d = q - centre;
    const double dist = std::hypot(d.x, d.y);
    if (dist >= radius) return std::nullopt;
    if (dist > 1e-9) return std::make_pair(radius - dist, (1.0 / dist) * d);
    // The centre is inside the body: out along the body axis of least penetration.
    const V2 p = centre - body.c;
    const double pu = dot(p, body.u), pv = dot(p, body.v);
    const double du = body.hu - std::abs(pu) + radius, dv = body.hv - std::abs(pv) + radius;
    if (du < dv) return std::make_pair(du, (pu >= 0 ? -1.0 : 1.0) * body.u);
    return std::make_pair(dv, (pv >= 0 ? -1.0 : 1.0) * body.v);
}

double point_segment(V2 p, V2 a, V2 b) {
    const V2 ab = b - a;
    const double len2 = dot(ab, ab);
    const double t = len2 > 0 ? std::clamp(dot(p - a, ab) / len2, 0.0, 1.0) : 0.0;
    const V2 d = p - (a + t * ab);
    return std::hypot(d.x, d.y);
}

// Distance between two rectangles that do not overlap (0 when they do).
double rect_rect_distance(const Rect& a, const Rect& b) {
    if (rect_rect(a, b)) return 0;
    const auto ca = a.corners(), cb = b.corners();
    double m = std::numeric_limits<double>::infinity();
    for (int i = 0; i < 4; ++i) {
        for (int j = 0; j < 4; ++j) {
            m = std::min(m, point_segment(ca[i], cb[j], cb[(j + 1) % 4]));
            m = std::min(m, point_segment(cb[i], ca[j], ca[(j + 1) % 4]));
        }
    }
    return m;
}

}  // namespace

const char* to_string(ContactKind k) {
    switch (k) {
        case ContactKind::Obstacle:
            return "obstacle";
        case ContactKind::Wall:
            return "wall";
        case ContactKind::Floor:
            return "floor";
        case ContactKind::Ceiling:
            return "ceiling";
    }
    return "?";
}

Collider::Collider(const Scene& scene, CollisionParams params) : params_(params) {
    x_min_ = scene.room.x_min_m;
    x_max_ = scene.room.x_max_m;
    y_min_ = scene.room.y_min_m;
    y_max_ = scene.room.y_max_m;
    height_ = scene.room.height_m;
    shapes_.reserve(scene.obstacles.size());
    for (std::size_t i = 0; i < scene.obstacles.size(); ++i) {
        const Obstacle& o = scene.obstacles[i];
        Shape s;
        s.cylinder = o.shape == ObstacleShape::Cylinder;
        s.x = o.x_m;
        s.y = o.y_m;
        s.z0 = o.z_m;
        s.z1 = o.z_m + o.height_m;
        s.hx = o.size_x_m / 2;
        s.hy = o.size_y_m / 2;
        s.radius = o.radius_m;
        s.yaw_rad = o.yaw_deg * kRadPerDeg;
        s.what = o.id.empty() ? "obstacle " + std::to_string(i) : o.id;
        shapes_.push_back(std::move(s));
    }
}

std::optional<Contact> Collider::contact(double x, double y, double z, double yaw_deg) const {
    const BodyShape& b = params_.body;
    const Rect body = make_rect(x, y, b.length_m / 2, b.width_m / 2, yaw_deg * kRadPerDeg);
    const double top = z + b.height_m;
    std::optional<Contact> best;
    auto consider = [&](ContactKind kind, std::size_t index, const std::string& what, double nx,
                        double ny, double nz, double depth) {
        if (depth <= 0 || (best && best->depth_m >= depth)) return;
        best = Contact{kind, index, what, nx, ny, nz, depth};
    };
    for (std::size_t i = 0; i < shapes_.size(); ++i) {
        const Shape& s = shapes_[i];
        const double vertical = std::min(top - s.z0, s.z1 - z);  // overlap of the height spans
        if (vertical <= 0) continue;
        const auto hit = s.cylinder ? rect_circle(body, {s.x, s.y}, s.radius)
                                    : rect_rect(body, make_rect(s.x, s.y, s.hx, s.hy, s.yaw_rad));
        if (!hit) continue;
        if (vertical < hit->first) {
            // Less inside vertically than across: the body touches the obstacle's top or bottom.
            const bool above = z + b.height_m / 2 > (s.z0 + s.z1) / 2;
            consider(ContactKind::Obstacle, i, s.what, 0, 0, above ? 1 : -1, vertical);
        } else {
            consider(ContactKind::Obstacle, i, s.what, hit->second.x, hit->second.y, 0, hit->first);
        }
    }
    const double ex = body.radius_on({1, 0}), ey = body.radius_on({0, 1});
    consider(ContactKind::Wall, 0, "front wall", -1, 0, 0, x + ex - x_max_);
    consider(ContactKind::Wall, 0, "back wall", 1, 0, 0, x_min_ - (x - ex));
    consider(ContactKind::Wall, 0, "right wall", 0, -1, 0, y + ey - y_max_);
    consider(ContactKind::Wall, 0, "left wall", 0, 1, 0, y_min_ - (y - ey));
    consider(ContactKind::Ceiling, 0, "ceiling", 0, 0, -1, top - height_);
    consider(ContactKind::Floor, 0, "floor", 0, 0, 1, -z);
    return best;
}

double Collider::clearance(double x, double y, double z, double yaw_deg, bool walls) const {
    const BodyShape& b = params_.body;
    const Rect body = make_rect(x, y, b.length_m / 2, b.width_m / 2, yaw_deg * kRadPerDeg);
    const double top = z + b.height_m;
    const double ex = body.radius_on({1, 0}), ey = body.radius_on({0, 1});
    double m =
        walls
            ? std::min({x_max_ - (x + ex), (x - ex) - x_min_, y_max_ - (y + ey), (y - ey) - y_min_})
            : std::numeric_limits<double>::infinity();
    for (const Shape& s : shapes_) {
        if (std::min(top - s.z0, s.z1 - z) <= 0) continue;
        if (s.cylinder) {
            const V2 q = closest_in(body, {s.x, s.y});
            m = std::min(m, std::hypot(q.x - s.x, q.y - s.y) - s.radius);
        } else {
            m = std::min(m, rect_rect_distance(body, make_rect(s.x, s.y, s.hx, s.hy, s.yaw_rad)));
        }
    }
    return std::max(0.0, m);
}

}  // namespace gs::sim
