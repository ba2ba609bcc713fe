// Errors raised for bad user input (files, options, scenarios).
//
// docs/design.md §2: bad user input throws trackassoc::InputError. Its message names the file, the dataset
// or field, what was expected and what was found. The CLI prints it on one line and exits with 2.
// Internal invariants use assertions instead.
#pragma once

#include <stdexcept>
#include <string>

namespace trackassoc {

class InputError : public std::runtime_error {
 public:
  explicit InputError(const std::string& what) : std::runtime_error(what) {}
};

// Throws InputError("<where>: <message>") when `condition` is false. Used by the validate()
// methods of every Options struct, so the message names the field.
inline void require(bool condition, const std::string& where, const std::string& message) {
  if (!condition) throw InputError(where + ": " + message);
}

}  // namespace trackassoc
