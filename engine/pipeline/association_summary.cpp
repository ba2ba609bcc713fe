// AssociationSummary's reports (engine/pipeline/associator.hpp): the text `associate`, `run` and the
// Python module print, from the typed fields alone.
#include <cmath>
#include <cstdio>
#include <sstream>

#include "engine/pipeline/associator.hpp"

namespace trackassoc {
namespace {

// A number as the CLI's tables print it (engine/report/text_table.hpp's fmt; NaN: "-").
std::string fmt(double v, const char* f = "%.4g") {
  if (std::isnan(v)) return "-";
  char buf[64];
  std::snprintf(buf, sizeof buf, f, v);
  return buf;
}

// The registration line, then per sensor but the reference its estimates ± standard errors
// (angles in degrees).
void registration_lines(std::ostream& os, const RegistrationRecord& r) {
  const std::size_t k = r.parameters.size();
  os << "registration (reference sensor " << r.reference_sensor << ", Wald " << fmt(r.wald, "%.1f") << " on "
     << r.wald_dof << " dof, " << r.observations << " observations): "
     << (r.applied ? "applied, " + std::to_string(r.rounds) + " associations"
         : r.rounds == 1 && std::isfinite(r.effect)
             ? "significant, but its largest effect " + fmt(r.effect, "%.2f") +
                   " sigma^2 per scan is below the bar, reports left as recorded"
         : r.rounds == 1
             ? std::string("not significant, reports left as recorded")
             : std::string("the corrected reports linked no more tracks, reports left as recorded"))
     << "\n";
  for (std::size_t s = 0; s < r.sensor.size(); ++s) {
    if (r.sensor[s] == r.reference_sensor) continue;
    os << "  sensor " << r.sensor[s] << ":";
    for (std::size_t j = 0; j < k; ++j) {
      const bool angle = r.parameters[j].find("azimuth") == 0 || r.parameters[j].find("elevation") == 0;
      const double f = angle ? 180.0 / 3.14159265358979323846 : 1.0;
      os << (j ? ", " : " ") << r.parameters[j] << " " << fmt(f * r.estimate[s * k + j], "%.4g") << " +- "
         << fmt(f * r.standard_error[s * k + j], "%.2g")
         << (angle                               ? " deg"
             : r.parameters[j] == "clock_offset" ? " s"
                                                 : " m");
    }
    os << "\n";
  }
}

// The sparse S-D path's counts after its stages: the fallback and listed components, the largest
// gap, the segment pass and the stitching.
void sparse_sd_counts(std::ostream& os, const AssociationSummary& s) {
  os << ", fallback components " << s.fallback_components;
  if (s.listed_components > 0)
    os << ", components over listed tuples " << s.listed_components << " (largest " << s.largest_listed_tuples
       << " tuples)";
  os << ", largest component gap " << fmt(100.0 * s.largest_component_gap, "%.2f") << " %";
  if (s.components_above_1pct_gap > 0) os << " (" << s.components_above_1pct_gap << " above 1 %)";
  if (s.segments)
    os << ", segments joined " << s.segments->joined << " (to " << s.segments->targets_joined
       << " targets; duplicates " << s.segments->duplicates << ")";
  if (s.stitching.stitches > 0) {
    const TrackStitchSummary& st = s.stitching;
    os << ", fragments stitched " << st.stitches << " (" << st.candidates << " gated continuations of "
       << st.groups << " targets";
    if (st.turn_probability > 0.0) {  // what it learnt from the file
      os << "; manoeuvre weight " << fmt(st.turn_probability, "%.3f");
      if (st.manoeuvre_interval_s > 0.0)
        os << ", a manoeuvre every " << fmt(st.manoeuvre_interval_s, "%.0f") << " s";
      if (st.quiet_sigma > 0.0) os << ", quiet sigma_a " << fmt(st.quiet_sigma, "%.2f") << " m/s^2";
      os << " learnt";
    }
    os << ")";
  }
}

}  // namespace

std::string AssociationSummary::BriefReport() const {
  std::string dims;
  for (int32_t n : track_counts) {
    if (!dims.empty()) dims += 'x';
    dims += std::to_string(n);
  }
  std::string what, result = "objective " + fmt(objective) + ", ";
  switch (path) {
    case AssociationPath::kSparseSD:
      what = "the tracks of " + std::to_string(file_sensors) + " sensors (sparse S-D, " +
             std::to_string(components) + " components)";
      break;
    case AssociationPath::kDenseSD:
      what = dims + " tracks of " + std::to_string(sensor_ids.size()) + " sensors (S-D)";
      result += "lower bound " + fmt(lower_bound) + ", ";
      break;
    case AssociationPath::kDense3D:
      what = dims + " tracks";
      break;
    case AssociationPath::kSparse3D:
      what = dims + " tracks (sparse: " + std::to_string(components) + " components)";
      break;
    case AssociationPath::kFusionCentre:
      what = std::to_string(local_tracks) + " local tracks (" + std::to_string(packets) + " packets)";
      result = std::to_string(system_tracks) + " system tracks, ";
      break;
    case AssociationPath::kSiamese:
      what = dims + " tracks of sensors " + std::to_string(sensor_ids.at(0)) + " and " +
             std::to_string(sensor_ids.at(1));
      result.clear();
      break;
  }
  return "associated " + what + " with '" + solver + "': " + result + std::to_string(tuples) + " tuples" +
         (termination.empty() ? "" : " (" + termination + ")") + ", " + fmt(1e3 * runtime_s, "%.2f") + " ms";
}

std::string AssociationSummary::FullReport() const {
  std::ostringstream os;
  os << BriefReport() << "\n";
  os << "pipeline: " << plan_of(path).describe() << "\n";
  if (!stages.empty()) {  // the tensor paths: the default, --sparse, and the dense --3d and --sd
    os << "stages:";
    for (const auto& st : stages) os << " " << st.name << " " << fmt(1e3 * st.seconds, "%.1f") << " ms;";
    os << " candidate pairs " << candidate_pairs << ", gated " << gated_pairs;
    if (path == AssociationPath::kSparseSD) sparse_sd_counts(os, *this);
    os << "\n";
    os << "peak memory (resident, at the end of each stage):";
    for (const auto& st : stages) os << " " << st.name << " " << fmt(st.peak_rss_mib, "%.0f") << " MiB;";
    os << "\n";
  }
  if (!empty_sensors.empty()) {
    os << "sensors with no local tracks:";
    for (std::size_t i = 0; i < empty_sensors.size(); ++i) os << (i ? ", " : " ") << empty_sensors[i];
    os << " (associated around; their column of the tuples is -1)\n";
  }
  if (!unfiltered_sensors.empty()) {
    os << "reports with independent errors (not a filter's output: no manoeuvre-lag widening):";
    for (std::size_t i = 0; i < unfiltered_sensors.size(); ++i)
      os << (i ? ", " : " ") << "sensor " << unfiltered_sensors[i].sensor << " (whiteness "
         << fmt(unfiltered_sensors[i].whiteness, "%.2f") << ")";
    os << "\n";
  }
  if (registration) registration_lines(os, *registration);
  os << "unassociated local tracks:";
  for (std::size_t i = 0; i < unassociated.size() && i < sensor_ids.size(); ++i)
    os << (i ? ", " : " ") << "sensor " << sensor_ids[i] << " " << unassociated[i];
  os << "\n";
  if (split.cuts > 0)
    os << "split " << split.cuts << " recycled track number(s) into new local tracks (" << split.gaps
       << " gaps tested; /tracks/source_track keeps the recorded numbers)\n";
  if (split.swaps > 0)
    os << "split " << split.swaps << " pair(s) of local tracks that swapped targets at a crossing into new "
       << "local tracks (/tracks/source_track keeps the recorded numbers)\n";
  return os.str();
}

}  // namespace trackassoc
