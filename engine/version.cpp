#include "engine/version.hpp"
namespace trackassoc {
const char* created_by() { return "trackassoc 0.1.0"; }
}  // namespace trackassoc
