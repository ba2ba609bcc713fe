// The fields of an association request (AssociatorOptions, engine/pipeline/associator.hpp) by name,
// declared once with OptionFields (engine/solvers/option_fields.hpp): the keyword arguments of the
// Python module's trackassoc.associate (engine/python/), read with the same type and range checks,
// "did you mean" and one-line errors as a solver's --options, then validated by the structs'
// validate(). Keys are the `associate` flags without "--" and with '_' for '-' (three_d for --3d,
// sensor_ids for --sensors, options for --options, model for --model, segments = not --no-segments).
#pragma once

#include <nlohmann/json.hpp>
#include <string>

#include "engine/pipeline/associator.hpp"
#include "engine/solvers/option_fields.hpp"

namespace trackassoc {

const OptionFields<AssociatorOptions>& associator_option_fields();

// AssociatorOptions{} with `fields` (a JSON object) read into it, then the request, its pipeline
// options and its segment options validated. Errors are InputErrors starting with `caller` + ": ".
AssociatorOptions read_associator_options(const nlohmann::json& fields, const std::string& caller);

}  // namespace trackassoc
