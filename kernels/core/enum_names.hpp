// One enum <-> name mapping for every option enum (docs/design.md §2: options in, names in JSON, HDF5 and
// on the command line).
//
// Each enum declares, beside itself, one constexpr table of its enumerators and their names, and
// an `enum_names` overload that returns it (found by argument-dependent lookup):
//
//   inline constexpr EnumName<StepRule> kStepRuleNames[]{
//       {StepRule::kPolyak, "polyak"}, {StepRule::kDiminishing, "diminishing"}, ...};
//   constexpr std::span<const EnumName<StepRule>> enum_names(StepRule) { return kStepRuleNames; }
//
// From that table come enum_name(e) (the name), parse_enum<E>(text, what) (the enumerator, or an
// InputError "what: expected a, b or c, found 'x'") and enum_name_list<E>() (the names for a help
// text). A name may carry a note ("power-mean", "Eq. 9"), shown in the list as "power-mean (Eq. 9)".
// No JSON here: kernels use it too (engine/solvers/option_fields.hpp reads and writes enum fields with it).
#pragma once

#include <span>
#include <string>
#include <string_view>

#include "kernels/core/error.hpp"

namespace trackassoc {

template <class E>
struct EnumName {
  E value;
  const char* name;
  const char* note = nullptr;  // shown after the name in lists and errors, e.g. "Eq. 9"
};

// The name of `e` ("?" for a value outside the table, which a valid enumerator never is).
template <class E>
const char* enum_name(E e) {
  for (const auto& n : enum_names(e))
    if (n.value == e) return n.name;
  return "?";
}

// "a, b or c" (with notes: "a (Eq. 9), b (Eq. 10) or c (Eq. 11)"), in table order.
template <class E>
std::string enum_name_list() {
  const auto names = enum_names(E{});
  std::string list;
  for (std::size_t i = 0; i < names.size(); ++i) {
    if (i > 0) list += i + 1 == names.size() ? " or " : ", ";
    list += names[i].name;
    if (names[i].note) list += std::string(" (") + names[i].note + ")";
  }
  return list;
}

// The enumerator named `text`; otherwise InputError("<what>: expected <list>, found '<text>'").
template <class E>
E parse_enum(std::string_view text, const std::string& what) {
  for (const auto& n : enum_names(E{}))
    if (text == n.name) return n.value;
  throw InputError(what + ": expected " + enum_name_list<E>() + ", found '" + std::string(text) + "'");
}

}  // namespace trackassoc
