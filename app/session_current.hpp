#pragma once
// The session's private parts shared by its files (app/session*.cpp), session thread only:
//   session.cpp            construction, the thread's loop, requests (the visitor), publishing
//   session_sources.cpp    source lifecycle: open a drone, the virtual drone or a replay; close
//   session_replay.cpp     replay control: pacing, stepping, seeking, looping
//   session_recording.cpp  recording control and the disk-space polling
//   session_camera.cpp     camera tracking and the calibration in use
//   session_frames.cpp     frame processing (classifier or odometry) and stale-video detection

#include "app/session.hpp"
#include "drone/video/frame_pool.hpp"

namespace gs::app {

inline constexpr TimeNs kIdleWaitNs = ms_to_ns(20);
inline constexpr std::size_t kImagePool = 6;
// Frames already queued or on the wire when a camera switch is seen may still be of the other
// camera: this many are shown but given to neither the classifier nor the odometry.
inline constexpr int kCameraSettleFrames = 3;

// The front camera's default (assets/calibration/, else the same numbers compiled in:
// docs/protocol.md §6.2), and the bottom camera's (assets/calibration/ardrone2_bottom.json).
// app/session_camera.cpp.
CameraCalibration front_calibration();
CameraCalibration bottom_calibration();

// Everything about the open source; lives on the session thread.
struct Session::Current {
    SessionSource kind = SessionSource::None;
    std::uint64_t id = 0;
    std::string address, scenario, path;
    std::shared_ptr<sim::VirtualDrone> drone;
    std::shared_ptr<link::DroneLink> link;
    std::shared_ptr<BoundedQueue<FrameSample>> frames;
    std::unique_ptr<dataset::DatasetSource> replay;
    ReplayInfo rinfo;
    // A replayed image is copied into a buffer the pipeline owns, because the dataset reader
    // reuses its own for the next frame while the window may still be drawing the previous one:
    // the video receiver's pool (explicit acquire and release, no reference count read).
    std::shared_ptr<video::FramePool> pool = video::FramePool::create(kImagePool);
    // The video's camera: the dataset's (replay) or the drone's configuration (live).
    CameraId camera = CameraId::Front;
    std::uint64_t config_gen = 0;
    int settle = 0;  // frames still to skip after a camera switch
    // Pipeline rate.
    TimeNs rate_t0 = 0;
    std::uint64_t rate_n = 0;
    double fps = kUnknown;
};

}  // namespace gs::app
