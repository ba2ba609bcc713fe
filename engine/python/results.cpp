#include "engine/python/results.hpp"

#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <numeric>

#include "engine/python/arrays.hpp"

namespace trackassoc::python {

std::mutex& hdf5_mutex() {
  static std::mutex m;
  return m;
}

namespace {

const char* path_name(AssociationPath p) {
  switch (p) {
    case AssociationPath::kSparseSD:
      return "sparse-sd";
    case AssociationPath::kDenseSD:
      return "dense-sd";
    case AssociationPath::kDense3D:
      return "dense-3d";
    case AssociationPath::kSparse3D:
      return "sparse-3d";
    case AssociationPath::kFusionCentre:
      return "fusion-centre";
    case AssociationPath::kSiamese:
      return "siamese";
  }
  return "?";
}

std::vector<int32_t> sensor_ids(const TrackFile& f) {
  std::vector<int32_t> ids;
  for (const Sensor& s : f.sensors) ids.push_back(s.id);
  return ids;
}

py::dict summary_of(const PyAssociation& a) {
  const AssociationRecord& r = a.outcome.record;
  py::dict d;
  d["name"] = r.name;
  d["solver"] = r.solver;
  d["objective"] = r.objective;
  d["bound"] = r.lower_bound;
  d["gap"] = r.gap;
  d["termination"] = r.termination;
  d["runtime_s"] = r.runtime_s;
  d["seed"] = r.seed;
  d["options"] = json_to_python(nlohmann::json::parse(r.options_json));
  if (!a.computed) return d;
  const AssociationSummary& s = a.outcome.summary;
  d["path"] = path_name(s.path);
  d["pipeline"] = plan_of(s.path).describe();  // the stages, as `associate` prints them
  d["sensor_ids"] = s.sensor_ids;
  d["track_counts"] = s.track_counts;
  py::list stages;
  for (const StageReport& st : s.stages) {
    py::dict e;
    e["name"] = st.name;
    e["seconds"] = st.seconds;
    e["peak_rss_mib"] = st.peak_rss_mib;
    stages.append(e);
  }
  d["stages"] = stages;
  d["components"] = s.components;
  d["candidate_pairs"] = s.candidate_pairs;
  d["gated_pairs"] = s.gated_pairs;
  d["fallback_components"] = s.fallback_components;
  using namespace pybind11::literals;
  if (s.segments)  // the segment pass (engine/pipeline/track_segments.hpp), as `associate` prints it
    d["segments"] = py::dict("targets"_a = s.segments->targets, "joined"_a = s.segments->joined,
                             "duplicates"_a = s.segments->duplicates, "rounds"_a = s.segments->rounds,
                             "targets_joined"_a = s.segments->targets_joined,
                             "targets_merged"_a = s.segments->targets_merged);
  if (s.stitching.groups > 0)  // fragment stitching (engine/pipeline/track_stitching.hpp)
    d["stitching"] =
        py::dict("groups"_a = s.stitching.groups, "candidates"_a = s.stitching.candidates,
                 "stitches"_a = s.stitching.stitches, "turn_probability"_a = s.stitching.turn_probability,
                 "manoeuvre_interval_s"_a = s.stitching.manoeuvre_interval_s,
                 "quiet_sigma"_a = s.stitching.quiet_sigma);
  if (!s.unfiltered_sensors.empty()) {  // reports with independent errors, aligned without the lag terms
    py::list u;
    for (const UnfilteredSensor& x : s.unfiltered_sensors)
      u.append(py::dict("sensor"_a = x.sensor, "whiteness"_a = x.whiteness));
    d["unfiltered_sensors"] = u;
  }
  if (s.path == AssociationPath::kFusionCentre) {
    d["local_tracks"] = s.local_tracks;
    d["packets"] = s.packets;
    d["system_tracks"] = s.system_tracks;
  }
  if (s.path == AssociationPath::kSiamese) {
    d["points"] = s.points;
    d["points_outside_domain"] = s.points_outside_domain;
  }
  return d;
}

py::object registration_of(const PyAssociation& a) {
  if (!a.outcome.registration) return py::none();
  const RegistrationRecord& r = *a.outcome.registration;
  const std::size_t S = r.sensor.size(), k = r.parameters.size();
  py::dict d;
  d["reference_sensor"] = r.reference_sensor;
  d["sensor"] = to_array(r.sensor);
  d["parameters"] = r.parameters;
  d["estimate"] = to_array(r.estimate, S, k);
  d["standard_error"] = to_array(r.standard_error, S, k);
  d["covariance_scale"] = to_array(r.covariance_scale, S, S);
  d["applied"] = r.applied;
  d["rounds"] = r.rounds;
  d["wald"] = r.wald;
  d["wald_dof"] = r.wald_dof;
  d["observations"] = r.observations;
  return d;
}

py::dict fused_arrays(const PyFused& f) {
  const FusedTrackRecord& r = f.record;
  py::dict d;
  d["tuple"] = to_array(r.tuple);
  d["t"] = to_array(r.t);
  d["state"] = columns_to_array(r.state, r.size());
  d["cov"] = columns_to_array(r.cov, r.size());
  d["sources"] = to_array(r.sources);
  d["truth"] = to_array(r.truth);
  if (!r.omega.empty()) d["omega"] = to_array(r.omega, r.size(), static_cast<std::size_t>(r.num_sensors));
  return d;
}

}  // namespace

PyAssociation association_of_file(std::shared_ptr<const TrackFile> file, const AssociationRecord& rec) {
  PyAssociation a;
  a.input = std::move(file);
  a.outcome.record = rec;
  const std::vector<int32_t> ids = sensor_ids(*a.input);
  if (rec.unassociated.empty()) {
    a.outcome.unassociated = unassociated_tracks(*a.input, ids, rec);
  } else {
    for (int32_t id : ids) a.outcome.unassociated.push_back({id, {}});
    for (std::size_t i = 0; i + 1 < rec.unassociated.size(); i += 2)
      for (auto& u : a.outcome.unassociated)
        if (u.sensor_id == rec.unassociated[i]) u.tracks.push_back(rec.unassociated[i + 1]);
  }
  if (a.input->registration && a.input->registration->association == rec.name)
    a.outcome.registration = a.input->registration;
  return a;
}

void bind_results(py::module_& m) {
  py::class_<PyTrackFile>(m, "TrackFile",
                          "A schema v1 track set (read(path), or the arrays given to associate), validated "
                          "by the C++ readers. Pass it to associate(), fuse(), evaluate() or write().")
      .def_property_readonly(
          "tracks",
          [](const PyTrackFile& f) {
            py::dict d = tracks_to_python(f.file->tracks);
            if (!f.file->source_track.empty()) d["source_track"] = to_array(f.file->source_track);
            return d;
          },
          "/tracks as a dict of numpy arrays: sensor, track, t, state (N x D), cov (N x D(D+1)/2 packed), "
          "truth; "
          "source_track (the recorded track number) when associate split a recycled number.")
      .def_property_readonly(
          "sensors", [](const PyTrackFile& f) { return sensors_to_python(f.file->sensors); },
          "/sensors as a dict of numpy arrays (id, position (S x 3), sigma_*, period, offset, ...).")
      .def_property_readonly(
          "state_layout",
          [](const PyTrackFile& f) { return std::string(layout_name(f.file->tracks.layout)); },
          "The state columns: 'x,y,vx,vy' or 'x,y,z,vx,vy,vz'.")
      .def_property_readonly(
          "associations",
          [](const PyTrackFile& f) {
            py::dict d;
            for (const auto& rec : f.file->associations)
              d[py::str(rec.name)] = association_of_file(f.file, rec);
            return d;
          },
          "The /associations groups: name -> Association.")
      .def_property_readonly(
          "fused",
          [](const PyTrackFile& f) {
            py::dict d;
            for (const auto& rec : f.file->fused) d[py::str(rec.name)] = PyFused{f.file, rec, std::nullopt};
            return d;
          },
          "The /fused groups: name -> Fused.")
      .def_property_readonly(
          "has_truth", [](const PyTrackFile& f) { return f.file->truth.has_value(); },
          "Whether /truth is present.")
      .def_readonly("source", &PyTrackFile::source, "The path read, or 'tracks' for arrays.")
      .def("__repr__", [](const PyTrackFile& f) {
        return "<trackassoc.TrackFile " + f.source + ": " + std::to_string(f.file->sensors.size()) +
               " sensors, " + std::to_string(f.file->tracks.size()) + " rows, " +
               std::to_string(f.file->associations.size()) + " associations>";
      });

  py::class_<PyAssociation>(m, "Association",
                            "The result of associate() (or an /associations group of a file read).")
      .def_property_readonly(
          "tuples",
          [](const PyAssociation& a) {
            const auto& r = a.outcome.record;
            return to_array(r.tuples, r.num_tuples(), static_cast<std::size_t>(r.num_sensors));
          },
          "K x S int32: column s holds the /tracks/track number of sensor sensor_ids[s] in the tuple, -1 = "
          "none.")
      .def_property_readonly(
          "sensor_ids", [](const PyAssociation& a) { return to_array(sensor_ids(*a.input)); },
          "The sensor id of each tuple column (the /sensors order).")
      .def_property_readonly(
          "target",
          [](const PyAssociation& a) {
            const auto& r = a.outcome.record;
            std::vector<int32_t> t = r.target;
            if (t.empty()) {
              t.resize(r.num_tuples());
              std::iota(t.begin(), t.end(), 0);
            }
            return to_array(t);
          },
          "K int32 target numbers: tuples of one number are one target followed by several local tracks "
          "of a sensor (track segments); without segments each tuple is its own target (0..K-1).")
      .def_property_readonly(
          "cost", [](const PyAssociation& a) { return to_array(a.outcome.record.cost); },
          "K float64 tuple costs.")
      .def_property_readonly(
          "unassociated",
          [](const PyAssociation& a) {
            py::dict d;
            for (const auto& u : a.outcome.unassociated) d[py::int_(u.sensor_id)] = to_array(u.tracks);
            return d;
          },
          "sensor id -> int32 array of its local tracks in no tuple of two or more (ascending).")
      .def_property_readonly(
          "registration", &registration_of,
          "The default pipeline's registration (/registration), or None: dict of reference_sensor, "
          "sensor (ids), parameters (names), estimate and standard_error (S x k; angles in rad, "
          "lengths in m, clock in s), covariance_scale (S x S), applied, rounds, wald, wald_dof, "
          "observations.")
      .def_property_readonly(
          "name", [](const PyAssociation& a) { return a.outcome.record.name; },
          "The /associations group name.")
      .def_property_readonly(
          "summary", &summary_of,
          "dict: name, solver, objective, bound (Lagrangian lower bound, NaN when none), gap, "
          "termination, runtime_s, seed, options; for a computed association also path, "
          "pipeline (the stages chosen), sensor_ids, track_counts, stages [{name, seconds, peak_rss_mib}], "
          "components, candidate_pairs, gated_pairs, fallback_components; on the default path segments "
          "{targets, joined, duplicates, rounds, targets_joined, targets_merged} and stitching {groups, "
          "candidates, stitches, turn_probability, manoeuvre_interval_s, quiet_sigma} when they ran.")
      .def_property_readonly(
          "tracks",
          [](const PyAssociation& a) {
            return PyTrackFile{a.input, "tracks"};
          },
          "The TrackFile that was associated.")
      .def(
          "brief_report",
          [](const PyAssociation& a) {
            if (!a.computed)
              throw InputError("brief_report: a stored association has no summary (read back)");
            return a.outcome.summary.BriefReport();
          },
          "One line: what was associated, the result, tuples, termination, time (AssociationSummary).")
      .def(
          "full_report",
          [](const PyAssociation& a) {
            if (!a.computed) throw InputError("full_report: a stored association has no summary (read back)");
            return a.outcome.summary.FullReport();
          },
          "brief_report() and a line per stage result, as `trackassoc associate` prints it.")
      .def("__len__", [](const PyAssociation& a) { return a.outcome.record.num_tuples(); })
      .def("__repr__", [](const PyAssociation& a) {
        return "<trackassoc.Association '" + a.outcome.record.name +
               "': " + std::to_string(a.outcome.record.num_tuples()) + " tuples of " +
               std::to_string(a.outcome.record.num_sensors) + " sensors>";
      });

  py::class_<PyFused>(m, "Fused",
                      "Fused tracks of an association (fuse(), or a /fused group of a file read).")
      .def_property_readonly(
          "name", [](const PyFused& f) { return f.record.name; }, "The /fused group name.")
      .def_property_readonly(
          "association", [](const PyFused& f) { return f.record.association; }, "The association fused.")
      .def_property_readonly(
          "rule", [](const PyFused& f) { return f.record.rule; }, "naive, bsc or ci.")
      .def_property_readonly(
          "arrays", &fused_arrays,
          "dict of numpy arrays, one row per fused time: tuple, t, state (N x D), cov (N x "
          "D(D+1)/2 packed), sources (tracks fused), truth, and omega (N x S, ci only).")
      .def_property_readonly(
          "summary",
          [](const PyFused& f) {
            py::dict d;
            d["options"] = json_to_python(nlohmann::json::parse(f.record.options_json));
            d["cross_covariance"] = f.record.cross_covariance;
            d["rows"] = f.record.size();
            if (f.summary) {
              d["tuples"] = f.summary->tuples;
              d["fused_tuples"] = f.summary->fused_tuples;
              d["single_member"] = f.summary->single_member;
              d["no_overlap"] = f.summary->no_overlap;
              d["shrunk_cells"] = f.summary->shrunk_cells;
              d["runtime_s"] = f.summary->runtime_s;
              d["termination"] = f.summary->termination;
              d["registration"] = f.summary->registration;
            }
            return d;
          },
          "dict: options (its 'registration': True when the reports were corrected by the association's "
          "registration), cross_covariance, rows; for fuse() results also tuples, fused_tuples, "
          "single_member, no_overlap, shrunk_cells, runtime_s, termination, registration (what was "
          "done, in words).")
      .def("__len__", [](const PyFused& f) { return f.record.size(); })
      .def("__repr__", [](const PyFused& f) {
        return "<trackassoc.Fused '" + f.record.name + "' (" + f.record.rule +
               "): " + std::to_string(f.record.size()) + " rows>";
      });
}

}  // namespace trackassoc::python
