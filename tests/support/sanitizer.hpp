// Whether this build runs under AddressSanitizer: its shadow memory and quarantine are resident but
// not the program's, so tests that bound the resident set loosen or skip the bound there.
#pragma once

namespace trackassoc::testing_support {

#if defined(__SANITIZE_ADDRESS__)
constexpr bool kAddressSanitizer = true;
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
constexpr bool kAddressSanitizer = true;
#else
constexpr bool kAddressSanitizer = false;
#endif
#else
constexpr bool kAddressSanitizer = false;
#endif

}  // namespace trackassoc::testing_support
