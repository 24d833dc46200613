#pragma once
// The PiController sizes compiled once in pi_controller_sizes.cpp: N = 6 (the metrology frame's
// six force-sensor/actuator channels) and N = 1 (the cart example), in double and float.
#include "controller/runtime/pi_controller.hpp"

extern template class flexloop::controller::runtime::PiController<double, 6>;
extern template class flexloop::controller::runtime::PiController<float, 6>;
extern template class flexloop::controller::runtime::PiController<double, 1>;
extern template class flexloop::controller::runtime::PiController<float, 1>;
