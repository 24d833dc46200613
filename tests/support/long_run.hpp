#pragma once
// The step count of a long numerical run. Under the sanitizers (tools/sanitize: ASan + UBSan at
// -O1, 20x slower on these loops) a tenth of it: what they look for, an access out of bounds or
// undefined arithmetic, lies on the path every step takes, and a tenth of the run takes it too.
// The bounds over the full length (drift, rounding) are the ordinary build's, where tools/check
// runs every test at the length its name states.
namespace flexloop::test {

constexpr long long_run_steps(long steps) {
#if defined(__SANITIZE_ADDRESS__)
  return steps / 10;
#else
  return steps;
#endif
}

}  // namespace flexloop::test
