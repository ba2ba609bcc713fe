// JSON from the user (scenario files, --options, the generator options stored in data set and
// model files), parsed with the checks nlohmann's parser leaves out (docs/design.md §2):
// - nesting deeper than kMaxJsonDepth is refused while parsing, through the parser callback, so
//   that nothing later recurses through a 100 000-level value (dumping one for an error message
//   overflows the stack);
// - a key that appears twice in one object is refused (nlohmann keeps the last one silently; a
//   duplicated key is as suspicious as a misspelt one).
#pragma once

#include <nlohmann/json.hpp>
#include <string>

namespace trackassoc {

inline constexpr int kMaxJsonDepth = 64;  // objects and arrays inside one another

// Throws InputError "<source>: invalid JSON: ...", "<source>: JSON nested deeper than 64 levels
// ..." or "<source>: key 'k' appears twice in one object".
nlohmann::json parse_json_input(const std::string& text, const std::string& source);

}  // namespace trackassoc
