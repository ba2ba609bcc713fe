// Errors raised for bad user input (files, options, scenarios).
//
// docs/design.md §2: bad user input throws trackassoc::InputError. Its message names the file, the dataset
// or field, what was expected and what was found. The CLI prints it on one line and exits with 2.
// Internal invariants use assertions instead.
#pragma once

#include <concepts>
#include <stdexcept>
#include <string>
#include <string_view>

namespace trackassoc {

class InputError : public std::runtime_error {
 public:
  explicit InputError(const std::string& what) : std::runtime_error(what) {}
};

// Throws InputError("<where>: <message>") when `condition` is false. Used by the validate()
// methods of every Options struct, so the message names the field. Views, so that a check that
// passes allocates nothing for its literals.
inline void require(bool condition, std::string_view where, std::string_view message) {
  if (!condition) throw InputError(std::string(where) + ": " + std::string(message));
}

// The same with the message made only on failure, make() returning it: for checks on hot paths
// whose message formats numbers (a validate() called per block of pairs, a χ² quantile).
template <class MakeMessage>
requires std::invocable<MakeMessage>
inline void require(bool condition, std::string_view where, MakeMessage&& make) {
  if (!condition) throw InputError(std::string(where) + ": " + std::string(make()));
}

}  // namespace trackassoc
