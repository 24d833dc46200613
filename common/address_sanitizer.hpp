// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// FLEXLOOP_ADDRESS_SANITIZER is defined when this translation unit is built with AddressSanitizer:
// GCC says so with __SANITIZE_ADDRESS__, clang only through __has_feature (tools/sanitize builds
// with clang).
#if defined(__SANITIZE_ADDRESS__)
#define FLEXLOOP_ADDRESS_SANITIZER 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define FLEXLOOP_ADDRESS_SANITIZER 1
#endif
#endif
