#include "synthetic_helpers.hpp"

#include "vision/flow_classifier.hpp"

#include <algorithm>
#include <cmath>

namespace gs::vision::test {

CameraCalibration synthetic_calibration() {
    return CameraCalibration::ideal(640, 360, 60);
}

namespace {
constexpr double kSpeed = 1.0;  // m/s

bool take_off(Motion m) {
    return m == Motion::TakeOff || m == Motion::TakeOffObstacle;
}

// TakeOff's attitude and forward speed and distance at time t (s): integrated in 1 ms steps.
struct TakeOffState {
    double pitch_deg = 0, speed_mps = 0, z_m = 0;
};
TakeOffState take_off_at(double t) {
    const auto pitch = [](double s) {
        if (s <= 0.1) return 0.0;
        if (s <= 0.45) {
            const double u = (s - 0.1) / 0.35;
            return -11.0 * u * u * (3 - 2 * u);  // smoothstep
        }
        return std::min(-5.0, -11.0 + 4.0 * (s - 0.45));
    };
    TakeOffState st;
    const double dt = 1e-3;
    for (double s = 0; s < t - 1e-12; s += dt) {
        const double a = 9.81 * std::tan(-pitch(s) * CV_PI / 180) - 0.5 * st.speed_mps;
        st.speed_mps += a * dt;
        st.z_m += st.speed_mps * dt;
    }
    st.pitch_deg = pitch(t);
    return st;
}
}  // namespace

Flight make_flight(Motion m) {
    Flight f;
    f.motion = m;
    switch (m) {
        case Motion::SidePass:
            f.frames = 75;  // 3 m at 1 m/s
            f.planes.push_back(make_plane({0, 0, 30}, {1, 0, 0}, {0, 1, 0}, 44, 26, 0.08, 11));
            // Wall on the right, 0.6 m from the flight line, from 4 m to 16 m ahead.
            f.planes.push_back(make_plane({0.6, 0, 10}, {0, 0, 1}, {0, 1, 0}, 12, 3, 0.02, 12));
            break;
        case Motion::NearPass:
            f.frames = 75;
            f.planes.push_back(make_plane({0, 0, 30}, {1, 0, 0}, {0, 1, 0}, 44, 26, 0.08, 11));
            f.planes.push_back(make_plane({0.45, 0, 10}, {0, 0, 1}, {0, 1, 0}, 12, 3, 0.02, 12));
            break;
        case Motion::Approach:
            f.frames = 110;  // 5 m -> 0.64 m
            f.planes.push_back(make_plane({0, 0, 5}, {1, 0, 0}, {0, 1, 0}, 6.4, 3.8, 0.01, 21));
            break;
        case Motion::WidePass:
            f.frames = 75;
            f.planes.push_back(make_plane({0, 0, 30}, {1, 0, 0}, {0, 1, 0}, 44, 26, 0.08, 11));
            f.planes.push_back(make_plane({1.5, 0, 10}, {0, 0, 1}, {0, 1, 0}, 12, 3, 0.02, 13));
            break;
        case Motion::Floor:
            f.frames = 75;
            f.planes.push_back(make_plane({0, 0, 30}, {1, 0, 0}, {0, 1, 0}, 44, 26, 0.08, 11));
            // 0.6 m below, from 2 m ahead (the bottom of the view is 1.85 m ahead) to 29 m.
            f.planes.push_back(make_plane({0, 0.6, 15.5}, {1, 0, 0}, {0, 0, 1}, 8, 27, 0.06, 14));
            break;
        case Motion::FloorWidePass:
            f.frames = 75;
            f.planes.push_back(make_plane({0, 0, 30}, {1, 0, 0}, {0, 1, 0}, 44, 26, 0.08, 11));
            f.planes.push_back(make_plane({0, 0.6, 15.5}, {1, 0, 0}, {0, 0, 1}, 8, 27, 0.06, 14));
            f.planes.push_back(make_plane({1.5, -0.9, 10}, {0, 0, 1}, {0, 1, 0}, 12, 3, 0.02, 13));
            break;
        case Motion::FloorObstacle:
            f.frames = 100;  // 5 m -> 1 m
            f.planes.push_back(make_plane({0, 0, 30}, {1, 0, 0}, {0, 1, 0}, 44, 26, 0.08, 11));
            f.planes.push_back(make_plane({0, 0.6, 15.5}, {1, 0, 0}, {0, 0, 1}, 8, 27, 0.06, 14));
            // Its foot on the floor (0.6 m below the camera), its top 0.9 m above it.
            f.planes.push_back(make_plane({0, -0.15, 5}, {1, 0, 0}, {0, 1, 0}, 1.2, 1.5, 0.01, 15));
            break;
        case Motion::Crossing:
            f.frames = 75;
            f.planes.push_back(make_plane({0, 0, 30}, {1, 0, 0}, {0, 1, 0}, 44, 26, 0.08, 11));
            // 0.5 x 1.75 m, facing the camera, starting 0.4 m right of the flight line (inside
            // the centre band), walking right: out of the corridor at once, never in the way.
            f.planes.push_back(make_plane({0.4, 0, 7}, {1, 0, 0}, {0, 1, 0}, 0.5, 1.75, 0.01, 41));
            f.moving_plane = 1;
            f.plane_velocity = {1.3, 0, 0};
            break;
        case Motion::TakeOff:
        case Motion::TakeOffObstacle:
            f.frames = 40;  // 1.6 s, 1.1 m
            f.planes.push_back(make_plane({0, 0, 30}, {1, 0, 0}, {0, 1, 0}, 44, 26, 0.08, 11));
            // 1.1 m below, from 1.8 m ahead to 30 m.
            f.planes.push_back(
                make_plane({0, 1.1, 15.9}, {1, 0, 0}, {0, 0, 1}, 10, 28.2, 0.06, 14));
            if (m == Motion::TakeOffObstacle)  // its foot on the floor
                f.planes.push_back(
                    make_plane({0, 0.3, 3.5}, {1, 0, 0}, {0, 1, 0}, 1.2, 1.6, 0.01, 15));
            break;
        case Motion::Roll:
        case Motion::Yaw:
            f.frames = 75;
            f.planes.push_back(make_plane({0, 0, 8}, {1, 0, 0}, {0, 1, 0}, 20, 7, 0.02, 31));
            break;
    }
    return f;
}

CameraPose Flight::pose_at(int i) const {
    const double t = i / fps;
    CameraPose p;
    p.pitch_deg = 0;
    p.roll_deg = 0;
    p.yaw_deg = 0;
    switch (motion) {
        case Motion::SidePass:
        case Motion::NearPass:
        case Motion::Approach:
        case Motion::WidePass:
        case Motion::Floor:
        case Motion::FloorObstacle:
        case Motion::FloorWidePass:
        case Motion::Crossing:
            p.position = {0, 0, kSpeed * t};
            p.pitch_deg = pitch_wobble_deg * std::sin(2 * CV_PI * t);
            break;
        case Motion::TakeOff:
        case Motion::TakeOffObstacle: {
            const TakeOffState st = take_off_at(t);
            p.position = {0, 0, st.z_m};
            p.pitch_deg = st.pitch_deg;
            break;
        }
        case Motion::Roll:
            p.roll_deg = 10 * std::sin(2 * CV_PI * 0.5 * t);
            break;
        case Motion::Yaw:
            p.yaw_deg = -18 + 15 * t;
            break;
    }
    return p;
}

double Flight::distance_at(int i) const {
    const double z = kSpeed * i / fps;
    if (take_off(motion)) return 3.5 - take_off_at(i / fps).z_m;
    if (motion == Motion::Approach || motion == Motion::FloorObstacle) return 5 - z;
    if (motion == Motion::SidePass || motion == Motion::NearPass) return 4 - z;  // wall's near end
    return 8;
}

std::vector<FrameRecord> fly(const Flight& f, ObstacleClassifier& c) {
    const CameraCalibration calib = synthetic_calibration();
    std::vector<FrameRecord> out;
    cv::Mat img;
    std::vector<TexturedPlane> planes = f.planes;
    for (int i = 0; i < f.frames; ++i) {
        const CameraPose pose = f.pose_at(i);
        if (f.moving_plane >= 0) {
            const auto k = static_cast<std::size_t>(f.moving_plane);
            planes[k].origin = f.planes[k].origin + f.plane_velocity * (i / f.fps);
        }
        render_scene(planes, calib, pose, img);
        FrameInput in;
        in.image = img;
        in.t_ns = static_cast<std::int64_t>(std::llround(i * 1e9 / f.fps));
        in.attitude = {pose.roll_deg, pose.pitch_deg, pose.yaw_deg * f.navdata_yaw_scale};
        if (f.navdata_altitude && f.motion == Motion::Floor) in.altitude_m = 0.6;
        if (take_off(f.motion)) {
            // The navdata as it was navdata_lag_s before the frame.
            const TakeOffState nav = take_off_at(std::max(0.0, i / f.fps - f.navdata_lag_s));
            in.attitude.pitch_deg = nav.pitch_deg;
            if (f.navdata_altitude) in.altitude_m = 1.1;
            if (f.navdata_velocity) {
                in.vx_mps = nav.speed_mps;
                in.vy_mps = 0;
                in.vz_mps = 0;
            }
        } else if (f.navdata_velocity) {
            const bool moving = f.motion != Motion::Roll && f.motion != Motion::Yaw;
            in.vx_mps = moving ? kSpeed : 0.0;
            in.vy_mps = moving ? f.navdata_vy_bias_mps : 0.0;
            in.vz_mps = 0;
        }
        const FrameResult& r = c.process(in);
        FrameRecord rec;
        for (std::size_t k = 0; k < 3; ++k) {
            rec.unsafe[k] = r.regions[k].unsafe;
            rec.valid[k] = r.regions[k].valid;
            rec.score[k] = r.regions[k].score;
            rec.edge_m[k] = r.regions[k].edge_m;
        }
        rec.distance_m = f.distance_at(i);
        if (const auto* flow = dynamic_cast<const FlowClassifier*>(&c)) {
            rec.foe_source = static_cast<int>(flow->foe_source());
            rec.foe_x = static_cast<double>(flow->focus_of_expansion().x);
        }
        out.push_back(rec);
    }
    return out;
}

int first_unsafe(const std::vector<FrameRecord>& rec, Region r) {
    const auto k = static_cast<std::size_t>(r);
    int first = -1;
    for (std::size_t i = 0; i < rec.size(); ++i) {
        if (rec[i].unsafe[k]) {
            if (first < 0) first = static_cast<int>(i);
        } else {
            first = -1;
        }
    }
    return first;
}

int count_unsafe(const std::vector<FrameRecord>& rec, Region r) {
    int n = 0;
    for (const FrameRecord& f : rec) n += f.unsafe[static_cast<std::size_t>(r)] ? 1 : 0;
    return n;
}

}  // namespace gs::vision::test
