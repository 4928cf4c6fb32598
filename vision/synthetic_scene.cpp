#include "vision/synthetic_scene.hpp"

#include "drone/core/geometry.hpp"
#include "vision/stabilisation.hpp"

#include <opencv2/imgproc.hpp>

namespace gs::vision {

cv::Mat make_texture(int width, int height, std::uint64_t seed) {
    cv::RNG rng(seed);
    cv::Mat tex(height, width, CV_8UC1, cv::Scalar(128));
    const double area = static_cast<double>(width) * height;
    // Three octaves of blobs and bars so there are corners at every viewing distance.
    const struct {
        double r0, r1, density;
    } layers[] = {{12, 40, 0.6}, {4, 12, 0.9}, {1.5, 4, 1.2}};
    for (const auto& l : layers) {
        const double mean_r = (l.r0 + l.r1) / 2;
        const int n = static_cast<int>(l.density * area / (CV_PI * mean_r * mean_r));
        for (int i = 0; i < n; ++i) {
            const cv::Point c(rng.uniform(0, width), rng.uniform(0, height));
            const double r = rng.uniform(l.r0, l.r1);
            const cv::Scalar g(rng.uniform(0, 256));
            if (rng.uniform(0, 2) == 0) {
                cv::circle(tex, c, static_cast<int>(r), g, cv::FILLED, cv::LINE_AA);
            } else {
                const cv::Size2f sz(static_cast<float>(r * 2), static_cast<float>(r));
                cv::ellipse(tex, cv::RotatedRect(cv::Point2f(c), sz, rng.uniform(0.f, 180.f)), g,
                            cv::FILLED, cv::LINE_AA);
            }
        }
    }
    cv::GaussianBlur(tex, tex, cv::Size(3, 3), 0.7);
    return tex;
}

TexturedPlane make_plane(cv::Vec3d centre, cv::Vec3d dir_u, cv::Vec3d dir_v, double width_m,
                         double height_m, double texel_m, std::uint64_t seed) {
    TexturedPlane p;
    const int w = static_cast<int>(std::lround(width_m / texel_m));
    const int h = static_cast<int>(std::lround(height_m / texel_m));
    p.texture = make_texture(w, h, seed);
    p.axis_u = dir_u * texel_m;
    p.axis_v = dir_v * texel_m;
    p.origin = centre - p.axis_u * (w / 2.0) - p.axis_v * (h / 2.0);
    return p;
}

void render_scene(const std::vector<TexturedPlane>& planes, const CameraCalibration& calib,
                  const CameraPose& pose, cv::Mat& out) {
    out.create(calib.height, calib.width, CV_8UC1);
    out.setTo(128);
    // The scene's world has the camera's axes at zero attitude: its rotation to the camera is
    // the body's inverse attitude seen through the front mount.
    const cv::Matx33d r_cw = geom::to_cv(geom::camera_rotation(
        geom::Mount::Front,
        geom::world_from_body_matrix(pose.roll_deg, pose.pitch_deg, pose.yaw_deg).transpose()));
    const cv::Matx33d k = calib.camera_matrix();
    for (const TexturedPlane& p : planes) {
        const cv::Vec3d o = p.origin - pose.position;
        const cv::Matx33d basis(p.axis_u[0], p.axis_v[0], o[0], p.axis_u[1], p.axis_v[1], o[1],
                                p.axis_u[2], p.axis_v[2], o[2]);
        const cv::Matx33d h = k * r_cw * basis;
        cv::warpPerspective(p.texture, out, h, out.size(), cv::INTER_LINEAR,
                            cv::BORDER_TRANSPARENT);
    }
}

}  // namespace gs::vision
