#pragma once
// CPU renderer for the simulated AR.Drone cameras (no OpenGL in drone/). Each output pixel of the
// distorted 640x360 image owns a fixed ray (the calibration inverted once at construction), so
// the lens' barrel distortion is exact per pixel with no intermediate image or remap. Per frame:
// a visibility pass casts those rays against the scene's planar primitives (rectangles and discs)
// with block-level culling and a depth buffer, then a shading pass samples the mip-mapped
// procedural textures once per pixel. Deterministic: the same pose gives the same bytes.
// Preallocated buffers: no allocation per frame once the output image has its size.

#include "drone/core/camera_calibration.hpp"
#include "drone/core/expected.hpp"
#include "drone/core/geometry_fwd.hpp"
#include "drone/sim/scene.hpp"

#include <opencv2/core.hpp>

#include <memory>
#include <optional>
#include <span>
#include <string>

namespace gs::sim {

// Front looks along the body x axis (image right = body right); Bottom looks down (image top =
// body forward); Top looks up at the ceiling (image top = body forward, image right = body LEFT:
// mounted back to back with Bottom, as in the thesis' rig). Axes: geom::body_from_camera.
using CameraKind = geom::Mount;

enum class RenderError { InvalidCalibration, CalibrationNotInvertible };
std::string to_string(RenderError e);

struct RenderOptions {
    double lod_bias = 0.0;  // added to the mip level (positive: blurrier)
    // A glossy floor (the realism layer's glossy_floor_*): the floor's pixels are mixed with the
    // mirror image of the scene above it by this share (0 = matte, no mirror pass), the mirror
    // image blurred by a Gaussian of `floor_blur_deg` angular sigma as the camera sees it (a
    // rough finish). The mirror pass renders the scene once more, from the camera mirrored in
    // the floor plane.
    double floor_reflection = 0.0;
    double floor_blur_deg = 0.0;
};

struct RenderStats {
    int primitives = 0;        // in the scene
    int primitives_drawn = 0;  // survived culling in the last frame
    int textures = 0;          // distinct generated textures
};

class Renderer {
public:
    // Builds the primitive list and generates every texture (the slow part: ~10 ms a texture).
    [[nodiscard]] static Expected<Renderer, RenderError> create(const Scene& scene,
                                                                const CameraCalibration& calib,
                                                                CameraKind camera,
                                                                RenderOptions options = {});
    Renderer(Renderer&&) noexcept;
    Renderer& operator=(Renderer&&) noexcept;
    ~Renderer();

    // Renders the view from `camera_pose` (camera position and the drone's attitude, world frame
    // of scene.hpp) into `bgr_out` (CV_8UC3, calibration size; reallocated only if needed).
    void render(const Pose& camera_pose, cv::Mat& bgr_out);

    // Boxes that move (the realism layer's people): drawn from the next render() on, in place of
    // the last call's; their textures are generated on first use (~10 ms each) and kept. Only
    // boxes (ObstacleShape::Box) are drawn.
    void set_movers(std::span<const Obstacle> boxes);

    // Where a world point appears in the image under the same camera model; nullopt if it is
    // behind the camera.
    std::optional<cv::Point2d> project(const Pose& camera_pose, double x_m, double y_m,
                                       double z_m) const;

    // 1 / z (z: depth along the optical axis, m) of each pixel of the last render, row-major;
    // 0 where nothing was hit. For the realism layer's motion blur (drone/sim/realism.hpp).
    std::span<const float> inverse_depth() const;

    const CameraCalibration& calibration() const;
    CameraKind camera() const;
    RenderStats stats() const;

private:
    struct Impl;
    explicit Renderer(std::unique_ptr<Impl> impl);
    std::unique_ptr<Impl> impl_;
};

// The camera's axes (x right, y down, z optical) as columns in the renderer's world frame (x
// forward, y right, z down) at `pose`.
cv::Matx33d world_from_camera(const Pose& pose, CameraKind camera);

}  // namespace gs::sim
