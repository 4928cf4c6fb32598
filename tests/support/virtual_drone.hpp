#pragma once
// A virtual drone on loopback and the link configuration that reaches it, built one way for every
// test that flies one.

#include "drone/link/drone_link.hpp"
#include "drone/sim/virtual_drone.hpp"

#include <string>

namespace gs::test {

// A virtual drone in `scene` on 127.0.0.1 with ephemeral ports.
inline sim::VirtualDroneOptions loopback_drone_options(sim::Scene scene) {
    sim::VirtualDroneOptions vo;
    vo.bind_address = "127.0.0.1";
    vo.at_port = vo.navdata_port = vo.video_port = vo.control_port = 0;
    vo.scene = std::move(scene);
    return vo;
}

// The link to a started virtual drone: its four ports on 127.0.0.1.
inline link::LinkConfig link_config_for(const sim::VirtualDrone& drone) {
    link::LinkConfig lc;
    lc.drone_address = lc.bind_address = "127.0.0.1";
    lc.at_port = drone.at_port();
    lc.navdata_port = drone.navdata_port();
    lc.video_port = drone.video_port();
    lc.control_port = drone.control_port();
    return lc;
}

}  // namespace gs::test
