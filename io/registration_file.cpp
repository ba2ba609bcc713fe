// /registration: see io/registration_file.hpp.
#include "io/registration_file.hpp"

#include <nlohmann/json.hpp>
#include <sstream>

#include "io/hdf5_wrapper.hpp"
#include "kernels/core/error.hpp"

namespace trackassoc {

namespace {

std::string joined(const std::vector<std::string>& names) {
  std::string s;
  for (const auto& n : names) s += (s.empty() ? "" : ",") + n;
  return s;
}

std::vector<std::string> split(const std::string& s) {
  std::vector<std::string> out;
  std::stringstream ss(s);
  for (std::string item; std::getline(ss, item, ',');)
    if (!item.empty()) out.push_back(item);
  return out;
}

}  // namespace

void check_registration(const std::string& file, const RegistrationRecord& r, std::size_t S) {
  const std::size_t k = r.parameters.size();
  auto need = [&](bool ok, const std::string& what, const std::string& expected, std::size_t found) {
    if (!ok)
      throw InputError(file + ": /registration/" + what + ": expected " + expected + ", found " +
                       std::to_string(found));
  };
  need(r.sensor.size() == S, "sensor", std::to_string(S) + " entries (one per /sensors entry)",
       r.sensor.size());
  need(k > 0, "parameters", "at least one parameter", k);
  need(r.estimate.size() == S * k, r.parameters.front(), std::to_string(S * k) + " values",
       r.estimate.size());
  need(r.standard_error.size() == S * k, r.parameters.front() + "_se", std::to_string(S * k) + " values",
       r.standard_error.size());
  need(r.covariance.empty() || r.covariance.size() == S * k * k, "covariance",
       std::to_string(S * k * k) + " values (S x k x k)", r.covariance.size());
  need(r.covariance_scale.size() == S * S, "covariance_scale", std::to_string(S * S) + " values",
       r.covariance_scale.size());
  need(r.pair_observations.size() == S * S, "pair_observations", std::to_string(S * S) + " values",
       r.pair_observations.size());
}

void write_registration(const h5::Group& root, const std::optional<RegistrationRecord>& r) {
  if (!r) return;
  const h5::Group g = root.create_group("registration", /*track_order=*/true);
  const hsize_t S = r->sensor.size(), k = r->parameters.size();
  g.write_attribute("reference_sensor", r->reference_sensor);
  g.write_attribute("parameters", joined(r->parameters));
  g.write_attribute("applied", int32_t{r->applied ? 1 : 0});
  g.write_attribute("rounds", r->rounds);
  g.write_attribute("wald", r->wald);
  g.write_attribute("wald_dof", r->wald_dof);
  g.write_attribute("effect", r->effect);
  g.write_attribute("observations", static_cast<uint64_t>(r->observations));
  g.write_attribute("association", r->association);
  g.write_attribute("options", r->options_json);
  g.write_dataset("sensor", std::span<const int32_t>(r->sensor), {S});
  for (hsize_t j = 0; j < k; ++j) {
    std::vector<double> v(S), se(S);
    for (hsize_t s = 0; s < S; ++s) v[s] = r->estimate[s * k + j], se[s] = r->standard_error[s * k + j];
    g.write_dataset(r->parameters[j], std::span<const double>(v), {S});
    g.write_dataset(r->parameters[j] + "_se", std::span<const double>(se), {S});
  }
  if (!r->covariance.empty())
    g.write_dataset("covariance", std::span<const double>(r->covariance), {S, k, k});
  g.write_dataset("covariance_scale", std::span<const double>(r->covariance_scale), {S, S});
  g.write_dataset("pair_observations", std::span<const int64_t>(r->pair_observations), {S, S});
}

std::optional<RegistrationRecord> read_registration(const h5::Group& root, const std::string& file) {
  if (!root.has("registration")) return std::nullopt;
  const h5::Group g = root.open_group("registration");
  for (const char* attr : {"reference_sensor", "parameters"})
    if (!g.has_attribute(attr)) g.fail(attr, "missing attribute (required)");
  RegistrationRecord r;
  r.reference_sensor = static_cast<int32_t>(g.read_integer_attribute("reference_sensor"));
  r.parameters = split(g.read_string_attribute("parameters"));
  if (g.has_attribute("applied")) r.applied = g.read_integer_attribute("applied") != 0;
  if (g.has_attribute("rounds")) r.rounds = static_cast<int32_t>(g.read_integer_attribute("rounds"));
  if (g.has_attribute("wald")) r.wald = g.read_double_attribute("wald");
  if (g.has_attribute("effect")) r.effect = g.read_double_attribute("effect");
  if (g.has_attribute("wald_dof")) r.wald_dof = static_cast<int32_t>(g.read_integer_attribute("wald_dof"));
  if (g.has_attribute("observations"))
    r.observations = static_cast<int64_t>(g.read_unsigned_attribute("observations"));
  if (g.has_attribute("association")) r.association = g.read_string_attribute("association");
  if (g.has_attribute("options")) {
    r.options_json = g.read_string_attribute("options");
    // Lenient: a missing, unparsable or non-integer entry reads as "chosen by the stage".
    const nlohmann::json stage = nlohmann::json::parse(r.options_json, nullptr, false);
    const auto it = stage.is_object() ? stage.find("reference_sensor") : stage.end();
    r.reference_named = it != stage.end() && it->is_number_integer() && it->get<int64_t>() >= 0;
  }
  std::vector<hsize_t> dims;
  const std::vector<int64_t> ids = g.read_integers("sensor", 1, dims);
  r.sensor.assign(ids.begin(), ids.end());
  const std::size_t S = r.sensor.size(), k = r.parameters.size();
  r.estimate.assign(S * k, 0.0);
  r.standard_error.assign(S * k, 0.0);
  for (std::size_t j = 0; j < k; ++j) {
    const std::vector<double> v = g.read_doubles(r.parameters[j], 1, dims);
    const std::vector<double> se = g.read_doubles(r.parameters[j] + "_se", 1, dims);
    if (v.size() != S || se.size() != S)
      g.fail(r.parameters[j], "expected " + std::to_string(S) + " values (one per sensor)");
    for (std::size_t s = 0; s < S; ++s) r.estimate[s * k + j] = v[s], r.standard_error[s * k + j] = se[s];
  }
  if (g.has("covariance")) r.covariance = g.read_doubles("covariance", 3, dims);
  r.covariance_scale = g.read_doubles("covariance_scale", 2, dims);
  r.pair_observations = g.read_integers("pair_observations", 2, dims);
  check_registration(file, r, S);
  return r;
}

}  // namespace trackassoc
