// Whether this build runs under AddressSanitizer: its shadow memory and quarantine are resident but
// not the program's, so tests that bound the resident set loosen or skip the bound there.
#pragma once

#include "io/memory_budget.hpp"

namespace trackassoc::testing_support {

inline const bool kAddressSanitizer = address_sanitizer_build();

}  // namespace trackassoc::testing_support
