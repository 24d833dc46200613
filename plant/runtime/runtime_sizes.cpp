// The one place the compiled plant sizes are instantiated (see runtime_sizes.hpp).
#include "plant/runtime/runtime_sizes.hpp"

#define FLEXLOOP_INSTANTIATE_RUNTIME_PLANTS(NX, NU, NY) FLEXLOOP_RUNTIME_PLANTS(, NX, NU, NY)
FLEXLOOP_RUNTIME_SIZES(FLEXLOOP_INSTANTIATE_RUNTIME_PLANTS)
