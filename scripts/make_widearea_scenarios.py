#!/usr/bin/env python3
"""Writes data/scenarios/widearea.json and widearea_small.json (issue 31; the model:
engine/simulation/simulation_widearea.hpp). One network, two target densities: 16 radars on a
4 x 4 grid 450 km apart over 2000 x 2000 km, coverage 300-400 km, periods 4-12 s, 2 hours,
targets born and dying (stationary population: count = birth_rate x lifetime_mean), tracks
broken by fades. Usage: /usr/bin/python3 scripts/make_widearea_scenarios.py"""
import json
import os

KM = 1000.0
PERIODS = [4.0, 6.0, 8.0, 12.0, 10.0, 5.0, 12.0, 7.0, 9.0, 4.0, 11.0, 6.0, 8.0, 10.0, 5.0, 12.0]
RADII = [350, 300, 400, 330, 380, 320, 360, 400, 300, 370, 340, 390, 310, 350, 400, 330]
LIFETIME = 3600.0


def network():
    sensors = []
    for i in range(16):
        row, col = divmod(i, 4)
        sensors.append({
            "id": i,
            "position": [(325 + 450 * col) * KM, (325 + 450 * row) * KM, 0.0],
            "sigma_range": 100.0 + 25.0 * (i % 5),
            "sigma_bearing_deg": 0.2 + 0.025 * (i % 5),
            "sigma_elevation_deg": 0.0,
            "period": PERIODS[i],
            "offset": round((0.37 * i) % PERIODS[i], 2),
            "p_detect": 0.9,
            "clutter_rate": 0.0,
            "reliability": 1.0,
            "coverage_radius": RADII[i] * KM,
        })
    return sensors


def scenario(name, alive, what):
    return {
        "name": name,
        "description": (
            f"Wide-area network (issue 31), {what}: 16 radars on a 4 x 4 grid 450 km apart over 2000 x 2000 km "
            "(coverage radius 300-400 km, detection 0.9 rolling off over the outer 12 %, sigma_range 100-200 m, "
            "sigma_bearing 0.2-0.3 deg, periods 4-12 s), 2 hours. Targets: "
            f"{alive} alive at any time (born at {alive / LIFETIME:.4g}/s, living Exp(1 h)), "
            "150-280 m/s, manoeuvres every 5-15 min. Tracks break at fades (one per 150 s per radar and "
            "target, 20-120 s long), at 3 missed scans in a row and where the target leaves coverage; "
            "each re-initiation is a new local track number. CV Kalman local trackers sigma_a = 1 m/s^2. "
            "Written by scripts/make_widearea_scenarios.py."),
        "layout": "2d",
        "duration": 7200.0,
        "truth_step": 30.0,
        "seed": 1,
        "sensors": network(),
        "targets": [],
        "random_targets": {
            "count": alive,
            "area_min": [0.0, 0.0, 0.0],
            "area_max": [2000 * KM, 2000 * KM, 0.0],
            "speed_min": 150.0,
            "speed_max": 280.0,
            "heading_min_deg": 0.0,
            "heading_max_deg": 360.0,
            "process_noise": 0.05,
            "manoeuvres": {"interval_min": 300.0, "interval_max": 900.0, "duration_min": 30.0,
                           "duration_max": 90.0, "turn_rate_max_deg_s": 1.5, "acceleration_max": 1.0,
                           "p_turn": 0.7},
        },
        "tracker": {"filter": "cv", "process_noise": 1.0},
        "wide_area": {
            "edge_fraction": 0.12,
            "fade_rate": 1.0 / 150.0,
            "fade_duration_min": 20.0,
            "fade_duration_max": 120.0,
            "coast_scans": 3,
            "birth_rate": alive / LIFETIME,
            "lifetime_mean": LIFETIME,
        },
    }


here = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "data", "scenarios")
for name, alive, what in [("widearea", 7000, "the benchmark (~3 x 10^5 local tracks, ~6 x 10^6 rows)"),
                          ("widearea_small", 700, "CI-sized (~3 x 10^4 local tracks)")]:
    with open(os.path.join(here, name + ".json"), "w") as f:
        json.dump(scenario(name, alive, what), f, indent=2)
        f.write("\n")
