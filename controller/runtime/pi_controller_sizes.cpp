// The controller sizes the runtime is compiled for: 6 force channels (metrology frame), 1 (cart).
#include "controller/runtime/pi_controller_sizes.hpp"

template class flexloop::controller::runtime::PiController<double, 6>;
template class flexloop::controller::runtime::PiController<float, 6>;
template class flexloop::controller::runtime::PiController<double, 1>;
template class flexloop::controller::runtime::PiController<float, 1>;
