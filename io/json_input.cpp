#include "io/json_input.hpp"

#include <set>
#include <vector>

#include "kernels/core/error.hpp"
#include "kernels/core/printable_text.hpp"

namespace trackassoc {

nlohmann::json parse_json_input(const std::string& text, const std::string& source) {
  using json = nlohmann::json;
  const std::string not_text = not_utf8_text_reason(text, "UTF-8");
  if (!not_text.empty()) throw InputError(source + ": " + not_text);
  std::vector<std::set<std::string>> keys;
  // `depth` is the number of objects and arrays around the event's value.
  auto callback = [&](int depth, json::parse_event_t event, json& parsed) {
    if ((event == json::parse_event_t::object_start || event == json::parse_event_t::array_start) &&
        depth >= kMaxJsonDepth)
      throw InputError(source + ": JSON nested deeper than " + std::to_string(kMaxJsonDepth) +
                       " levels (objects and arrays inside one another); no input of trackassoc needs that");
    if (event == json::parse_event_t::object_start)
      keys.emplace_back();
    else if (event == json::parse_event_t::object_end) {
      if (!keys.empty()) keys.pop_back();
    } else if (event == json::parse_event_t::key && !keys.empty()) {
      const std::string key = parsed.get<std::string>();
      if (!keys.back().insert(key).second)
        throw InputError(source + ": key " + quoted_preview(key, 80) + " appears twice in one object");
    }
    return true;
  };
  try {
    return json::parse(text, callback);
  } catch (const json::exception& e) {
    throw InputError(source + ": invalid JSON: " + printable_text(e.what()));
  }
}

}  // namespace trackassoc
