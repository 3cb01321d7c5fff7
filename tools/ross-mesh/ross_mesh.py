#!/usr/bin/env python3
"""Mesh stiffness of two spur gear pairs from ROSS, an independent code, as a fixture for geardyn.

ROSS (`ross-rotordynamics` on PyPI) computes a time-varying mesh stiffness in
`ross/gear_element.py` (`GearElementTVMS`, `Mesh`) by the potential-energy method of Ma et al.
(2014): bending, shear and axial compression of the tooth with its fillet (transition) curve,
the fillet-foundation term of Sainsot, Velex & Duverger (2004) and the Hertz line contact of
Yang & Lin (1987). geardyn's `src/mesh/` implements the same family of formulas on its own;
this script records what ROSS gives on the same gears so that `tests/mesh_ross.rs` can compare.

Writes tests/data/ross-mesh.json (CI has no Python: only the committed JSON is read there). Run
from the repository root:

    python3 -m venv /tmp/ross-venv
    /tmp/ross-venv/bin/pip install ross-rotordynamics "plotly<7"
    /tmp/ross-venv/bin/python tools/ross-mesh/ross_mesh.py

(`plotly<7`: ROSS 2.3.0 registers a plotly template with `scattermapbox`, which plotly 7
removed; `import ross` fails without the pin.)

Cases, in geardyn's terms (rig.toml `[rig]` and `[geometry]`):

- `pair_62_62`: 62/62 teeth, module 2 mm, 20 deg, face 20 mm, bores 35 mm, E 211 GPa, nu 0.3;
- `munro`: Munro's gears as geardyn defines them (data/munro/rig.toml, `[geometry]` defaults of
  src/mesh/geometry.rs): 32/32 teeth, module 6.35 mm, 20 deg, face 12.7 mm, bores a third of
  the root diameter m (z - 2 h_f*) / 3 = 62.441667 mm, E 206 GPa, nu 0.3.

Both with ROSS's standard rack: addendum coefficient 1, tip clearance 0.25 (dedendum 1.25 m),
cutter tip radius 0.25 m / (1 - sin 20 deg) = 0.37995 m (geardyn's default is 0.38 m).

What is recorded per case (stiffness in N/um):

- `contact_ratio`: `Mesh.contact_ratio`;
- `mesh_period`: the stiffness over one mesh period at `SAMPLES` equally spaced points,
  `mesh_position` = theta / (2 pi / z1) in [0, 1), theta the driving gear's rotation angle (rad,
  also given) from the instant a new tooth pair enters contact (ROSS's `get_variable_stiffness`);
- `mean/max/min`: over ROSS's own table of the period (`Mesh.stiffness_range`, 1000 points of
  `np.linspace(0, 2 pi / z1, 1000)`, both ends included), and the mean of the samples above;
- `pitch_point`: the single-pair stiffness with both teeth loaded at the pitch point (profile
  pressure angle = 20 deg on both), 1 / (1/k_h + 1/k_1 + 1/k_2) from ROSS's
  `GearElementTVMS._compute_stiffness` and `Mesh.hertzian_stiffness` (private but stable
  methods; ROSS has no public single-pair call), with each tooth's compliances (m/N) from
  `_inv_kb`, `_inv_ks`, `_inv_ka`, `_inv_kf`;
- `mesh_stiffness_mean_line_of_action_n_per_um`: a diagnostic, not a ROSS output: ROSS's own
  pair stiffness (the same private calls) with the pairs placed where the line of action puts
  them, at roll distances s_A + (tau + j) p_b from the pinion's base-circle tangency point
  (pinion at profile pressure angle atan(s / r_b), gear at atan((a sin 20 deg - s) / r_b)),
  averaged over `LOA_SAMPLES` = 1000 positions tau = i / 1000. ROSS itself advances each tooth's profile pressure
  angle linearly in time from the basic rack's limit point (not the mating gear's start of
  active profile) to its tip, so its pairs do not sit on the line of action; this number
  separates that from its stiffness formulas;
- ROSS's inputs to the fillet-foundation term: root half-angle theta_f (built with the
  addendum coefficient h_a* where geardyn uses the rack's dedendum h_f*), root radius, bore
  ratio h = r_f / r_bore, and the load height at the pitch point u = y_c - r_f (geardyn measures
  it to where the line of action crosses the tooth's centre line).

The mass, inertia and density ROSS also computes do not enter the stiffness.
"""

import datetime
import importlib.metadata
import json
import os
import platform
import sys
import warnings

import numpy as np
import scipy

import ross
from ross.gear_element import GearElementTVMS, Mesh

OUTPUT = os.path.join("tests", "data", "ross-mesh.json")
SCRIPT = "tools/ross-mesh/ross_mesh.py"
SAMPLES = 48
# Positions of the line-of-action diagnostic: the share of two-pair positions is resolved to
# 1 / LOA_SAMPLES, so the mean to about 0.1% (48 would leave 1%).
LOA_SAMPLES = 1000
ADDENDUM = 1.0
TIP_CLEARANCE = 0.25
# Density only sets ROSS's gear masses, which do not enter the stiffness.
DENSITY_KG_M3 = 7810.0


def munro_bore_mm():
    """geardyn's default bore for Munro's gears: a third of the root diameter m (z - 2 h_f*)."""
    return 6.35 * (32 - 2 * (ADDENDUM + TIP_CLEARANCE)) / 3.0


CASES = [
    {
        "name": "pair_62_62",
        "description": "62/62 spur pair, module 2 mm, 20 deg, face 20 mm, bores 35 mm, "
        "E 211 GPa, nu 0.3 (the gears of ROSS's own Mesh example, with the stated material)",
        "pinion_teeth": 62,
        "gear_teeth": 62,
        "module_mm": 2.0,
        "pressure_angle_deg": 20.0,
        "face_width_mm": 20.0,
        "bore_diameter_mm": 35.0,
        "youngs_modulus_gpa": 211.0,
        "poisson_ratio": 0.3,
    },
    {
        "name": "munro",
        "description": "Munro's gears as geardyn defines them (data/munro/rig.toml with the "
        "[geometry] defaults: bores a third of the root diameter, E 206 GPa, nu 0.3)",
        "pinion_teeth": 32,
        "gear_teeth": 32,
        "module_mm": 6.35,
        "pressure_angle_deg": 20.0,
        "face_width_mm": 12.7,
        "bore_diameter_mm": munro_bore_mm(),
        "youngs_modulus_gpa": 206.0,
        "poisson_ratio": 0.3,
    },
]


def gear(node, case, teeth, material):
    """One ROSS gear of `case` (SI units)."""
    return GearElementTVMS(
        n=node,
        material=material,
        width=case["face_width_mm"] * 1e-3,
        bore_diameter=case["bore_diameter_mm"] * 1e-3,
        module=case["module_mm"] * 1e-3,
        n_teeth=teeth,
        pr_angle=np.radians(case["pressure_angle_deg"]),
        addendum_coeff=ADDENDUM,
        tip_clearance_coeff=TIP_CLEARANCE,
    )


def compliances(g, angle):
    """Compliances (m/N) of ROSS gear `g` loaded at profile pressure angle `angle` (rad)."""
    beta = g._to_tau(angle)
    return {
        "bending": float(g._inv_kb(beta)),
        "shear": float(g._inv_ks(beta)),
        "axial": float(g._inv_ka(beta)),
        "foundation": float(g._inv_kf(beta)),
    }


def line_of_action_mean(case, g1, g2, hertz):
    """Mean (N/um) of ROSS's pair stiffness summed over the pairs on the line of action, at
    `LOA_SAMPLES` mesh positions (standard centre distance, tips from the addendum)."""
    alpha = np.radians(case["pressure_angle_deg"])
    rb1, rb2 = g1.base_radius, g2.base_radius
    ra1, ra2 = g1.radii_dict["addendum"], g2.radii_dict["addendum"]
    t1t2 = (g1.pitch_diameter + g2.pitch_diameter) / 2 * np.sin(alpha)
    s_e = np.sqrt(ra1**2 - rb1**2)
    s_a = t1t2 - np.sqrt(ra2**2 - rb2**2)
    p_b = 2 * np.pi * rb1 / g1.n_teeth

    def pair(s):
        c1 = 1.0 / g1._compute_stiffness(np.arctan(s / rb1))
        c2 = 1.0 / g2._compute_stiffness(np.arctan((t1t2 - s) / rb2))
        return 1.0 / (hertz + c1 + c2)

    total = []
    for i in range(LOA_SAMPLES):
        rolls = [s_a + (i / LOA_SAMPLES + j) * p_b for j in range(4)]
        total.append(sum(pair(s) for s in rolls if s <= s_e + 1e-12 * p_b))
    return float(np.mean(total)) * 1e-6


def run(case):
    """ROSS's mesh stiffness for one case; returns the fixture's record."""
    material = ross.Material(
        name=f"mat_{case['name']}",
        rho=DENSITY_KG_M3,
        E=case["youngs_modulus_gpa"] * 1e9,
        Poisson=case["poisson_ratio"],
    )
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        g1 = gear(0, case, case["pinion_teeth"], material)
        g2 = gear(2, case, case["gear_teeth"], material)
        mesh = Mesh(g1, g2)
        period = 2 * np.pi / g1.n_teeth
        theta = [period * i / SAMPLES for i in range(SAMPLES)]
        k = [float(mesh.get_variable_stiffness(t)) * 1e-6 for t in theta]
        table = np.asarray(mesh.stiffness_range) * 1e-6
        alpha = np.radians(case["pressure_angle_deg"])
        c1, c2 = compliances(g1, alpha), compliances(g2, alpha)
        hertz = 1.0 / mesh.hertzian_stiffness
        k_pitch = 1.0 / (hertz + sum(c1.values()) + sum(c2.values()))
        y_c = g1._compute_involute_curve(g1._to_tau(alpha))[0]
        k_loa = line_of_action_mean(case, g1, g2, hertz)
    r_f = float(g1.radii_dict["root"])
    return {
        "name": case["name"],
        "description": case["description"],
        "inputs": {
            "pinion_teeth": case["pinion_teeth"],
            "gear_teeth": case["gear_teeth"],
            "module_mm": case["module_mm"],
            "pressure_angle_deg": case["pressure_angle_deg"],
            "face_width_mm": case["face_width_mm"],
            "bore_diameter_mm": case["bore_diameter_mm"],
            "youngs_modulus_gpa": case["youngs_modulus_gpa"],
            "poisson_ratio": case["poisson_ratio"],
            "addendum_coefficient": ADDENDUM,
            "tip_clearance_coefficient": TIP_CLEARANCE,
            "density_kg_per_m3": DENSITY_KG_M3,
        },
        "contact_ratio": float(mesh.contact_ratio),
        "mesh_stiffness_mean_n_per_um": float(table.mean()),
        "mesh_stiffness_max_n_per_um": float(table.max()),
        "mesh_stiffness_min_n_per_um": float(table.min()),
        "mesh_stiffness_table_points": int(table.size),
        "mesh_stiffness_sampled_mean_n_per_um": float(np.mean(k)),
        "mesh_stiffness_mean_line_of_action_n_per_um": k_loa,
        "mesh_period": {
            "abscissa": "mesh_position = theta / (2 pi / pinion_teeth) in [0, 1): the driving "
            "gear's rotation over one mesh period, 0 when a new tooth pair enters contact",
            "mesh_position": [i / SAMPLES for i in range(SAMPLES)],
            "driving_gear_angle_rad": theta,
            "stiffness_n_per_um": k,
        },
        "pitch_point": {
            "single_pair_stiffness_n_per_um": k_pitch * 1e-6,
            "hertz_compliance_m_per_n": hertz,
            "pinion_compliance_m_per_n": c1,
            "gear_compliance_m_per_n": c2,
        },
        "foundation_inputs": {
            "root_half_angle_rad": float(g1.tooth_dict["root_angle"]),
            "root_radius_mm": r_f * 1e3,
            "cutter_tip_radius_mm": float(g1.radii_dict["cutter_tip"]) * 1e3,
            "root_over_bore_radius": r_f / (0.5 * case["bore_diameter_mm"] * 1e-3),
            "pitch_point_load_height_mm": float(y_c - r_f) * 1e3,
        },
        "ross_warnings": sorted({str(w.message) for w in caught}),
    }


def main():
    records = [run(c) for c in CASES]
    out = {
        "provenance": {
            "script": SCRIPT,
            "command": f"python3 {SCRIPT} (from the repository root, in a venv with "
            "ross-rotordynamics and plotly<7)",
            "ross_rotordynamics": importlib.metadata.version("ross-rotordynamics"),
            "numpy": np.__version__,
            "scipy": scipy.__version__,
            "python": platform.python_version(),
            "platform": platform.platform(),
            "generated_utc": datetime.datetime.now(datetime.timezone.utc)
            .replace(microsecond=0)
            .isoformat(),
            "units": "lengths mm, angles deg (inputs) and rad, modulus GPa, stiffness N/um, "
            "compliance m/N",
            "ross_source": "ross/gear_element.py: GearElementTVMS, Mesh",
        },
        "cases": records,
    }
    with open(OUTPUT, "w") as f:
        json.dump(out, f, indent=1)
        f.write("\n")
    for r in records:
        print(
            f"{r['name']}: contact ratio {r['contact_ratio']:.6f}, mesh stiffness mean "
            f"{r['mesh_stiffness_mean_n_per_um']:.2f} (max {r['mesh_stiffness_max_n_per_um']:.2f}, "
            f"min {r['mesh_stiffness_min_n_per_um']:.2f}) N/um, pitch-point pair "
            f"{r['pitch_point']['single_pair_stiffness_n_per_um']:.2f} N/um",
            file=sys.stderr,
        )
    print(f"wrote {OUTPUT}", file=sys.stderr)


if __name__ == "__main__":
    main()
