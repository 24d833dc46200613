#pragma once
// The plant sizes (NX states, NU inputs, NY outputs) the runtime is compiled for, and a dispatch
// from the sizes of a loaded artefact to the matching compiled plant (README.md in this folder).
//
//   12/12/12  metrology frame: 12 suspension states; 6 floor accelerations + 6 actuator forces
//             in; 6 frame accelerations + 6 strut forces out
//   24/12/12  metrology frame under gravity preload (floor position and velocity as states)
//    2/2/2    cart example with a piezo between cart and mass (tools/models/cart_piezo.toml)
//
// The second half of the inputs are the actuator forces, which the plant holds from one sample to
// the next (NH = NU / 2 held inputs, plant/runtime/state_output.hpp); the first half are the
// sampled disturbances. DensePlant and ModalPlant of these sizes, in double and float, are
// instantiated once in runtime_sizes.cpp (the extern declarations below keep other files from
// compiling them again). These are fast paths: every other size runs on the general path, sized
// at start-up (general_plant.hpp), with no rebuild. To add a fast path: add a line to
// FLEXLOOP_RUNTIME_SIZES.
#include <stdexcept>
#include <string>

#include "plant/runtime/dense_plant.hpp"
#include "plant/runtime/modal_plant.hpp"

// X(NX, NU, NY) for every compiled size.
#define FLEXLOOP_RUNTIME_SIZES(X) \
  X(12, 12, 12)                   \
  X(24, 12, 12)                   \
  X(2, 2, 2)

#define FLEXLOOP_RUNTIME_PLANTS(PREFIX, NX, NU, NY)                                         \
  PREFIX template class flexloop::plant::runtime::DensePlant<double, NX, NU, NY, (NU) / 2>; \
  PREFIX template class flexloop::plant::runtime::DensePlant<float, NX, NU, NY, (NU) / 2>;  \
  PREFIX template class flexloop::plant::runtime::ModalPlant<double, NX, NU, NY, (NU) / 2>; \
  PREFIX template class flexloop::plant::runtime::ModalPlant<float, NX, NU, NY, (NU) / 2>;

#define FLEXLOOP_EXTERN_RUNTIME_PLANTS(NX, NU, NY) FLEXLOOP_RUNTIME_PLANTS(extern, NX, NU, NY)
FLEXLOOP_RUNTIME_SIZES(FLEXLOOP_EXTERN_RUNTIME_PLANTS)
#undef FLEXLOOP_EXTERN_RUNTIME_PLANTS

namespace flexloop::plant::runtime {

/// A compiled size as a type, handed to the callback of with_runtime_size.
template <int NX_, int NU_, int NY_>
struct RuntimeSize {
  static constexpr int NX = NX_, NU = NU_, NY = NY_;
  static constexpr int NH = NU / 2;  // held inputs: the actuator forces
};

/// Start-up: f(RuntimeSize<NX, NU, NY>{}) for the compiled size equal to (nx, nu, ny), otherwise()
/// when there is none (both must return the same type).
template <typename F, typename Otherwise>
decltype(auto) with_runtime_size(long nx, long nu, long ny, F&& f, Otherwise&& otherwise) {
#define FLEXLOOP_DISPATCH_SIZE(NX, NU, NY) \
  if (nx == NX && nu == NU && ny == NY) return f(RuntimeSize<NX, NU, NY>{});
  FLEXLOOP_RUNTIME_SIZES(FLEXLOOP_DISPATCH_SIZE)
#undef FLEXLOOP_DISPATCH_SIZE
  return otherwise();
}

/// Start-up: calls f(RuntimeSize<NX, NU, NY>{}) for the compiled size equal to (nx, nu, ny), and
/// returns what it returns (every call of f must return the same type).
/// @throws std::invalid_argument listing the compiled sizes when there is none such.
template <typename F>
decltype(auto) with_runtime_size(long nx, long nu, long ny, F&& f) {
#define FLEXLOOP_DISPATCH_SIZE(NX, NU, NY) \
  if (nx == NX && nu == NU && ny == NY) return f(RuntimeSize<NX, NU, NY>{});
  FLEXLOOP_RUNTIME_SIZES(FLEXLOOP_DISPATCH_SIZE)
#undef FLEXLOOP_DISPATCH_SIZE
  std::string known;
#define FLEXLOOP_LIST_SIZE(NX, NU, NY) \
  known += " " + std::to_string(NX) + "/" + std::to_string(NU) + "/" + std::to_string(NY);
  FLEXLOOP_RUNTIME_SIZES(FLEXLOOP_LIST_SIZE)
#undef FLEXLOOP_LIST_SIZE
  throw std::invalid_argument("the plant has " + std::to_string(nx) + " states, " +
                              std::to_string(nu) + " inputs and " + std::to_string(ny) +
                              " outputs; the runtime is compiled for (states/inputs/outputs)" +
                              known + " (add the size in plant/runtime/runtime_sizes.hpp)");
}

}  // namespace flexloop::plant::runtime
