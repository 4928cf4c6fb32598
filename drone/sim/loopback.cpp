#include "drone/sim/loopback.hpp"

namespace gs::sim {

VirtualDroneOptions loopback_options(Scene scene) {
    VirtualDroneOptions vo;
    vo.bind_address = "127.0.0.1";
    vo.at_port = vo.navdata_port = vo.video_port = vo.control_port = 0;  // ephemeral
    vo.scene = std::move(scene);
    return vo;
}

link::LinkConfig link_config(const VirtualDrone& drone) {
    link::LinkConfig lc;
    lc.drone_address = lc.bind_address = "127.0.0.1";
    lc.at_port = drone.at_port();
    lc.navdata_port = drone.navdata_port();
    lc.video_port = drone.video_port();
    lc.control_port = drone.control_port();
    return lc;
}

}  // namespace gs::sim
