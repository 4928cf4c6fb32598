#pragma once
// A virtual drone on loopback and the link configuration that reaches it: built here, one way, for
// every caller that flies one (the window's session, `ardrone-gs record --sim`, the tests).

#include "drone/link/drone_link.hpp"
#include "drone/sim/virtual_drone.hpp"

namespace gs::sim {

// A virtual drone in `scene` bound to 127.0.0.1 with ephemeral ports (see the bound ports on the
// started VirtualDrone); every other option at its default.
VirtualDroneOptions loopback_options(Scene scene);

// The link to a started virtual drone: its four bound ports on 127.0.0.1, every other link option
// at its default.
link::LinkConfig link_config(const VirtualDrone& drone);

}  // namespace gs::sim
