// Whether this build runs under AddressSanitizer, which reserves terabytes of address space for its
// shadow memory: a bound on the address space (RLIMIT_AS) cannot be set, nor tested, under it.
#pragma once

namespace hsr {

#if defined(__SANITIZE_ADDRESS__)
inline constexpr bool kAddressSanitizer = true;
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
inline constexpr bool kAddressSanitizer = true;
#else
inline constexpr bool kAddressSanitizer = false;
#endif
#else
inline constexpr bool kAddressSanitizer = false;
#endif

}  // namespace hsr
