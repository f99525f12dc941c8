"""The co-evolved hover creatures' gallery (doc/hovering.md): each committed creature flown by
flight_check --hover, with its shape from its body file."""
import os
import re

from doc_tables import ROOT, Run, Table
from doc_tables_flight import FLIGHT_CHECK, hover_report

# (label, URDF, gains, body file, the air's flags): the body file gives the wing's length and
# chord; each creature flies in the air it was evolved in.
CREATURES = [
    ("hover_1 (hand-designed body, evolved gains; its motors do not fit the budget)",
     "urdf/hover_1.urdf", "config/hover_1_gains.yaml", "config/hover_1_body.yaml",
     ["--added-mass-products", "omitted"]),
    ("`config/morph_116wkg` (co-evolved, the sourced 116 W/kg motors)",
     "config/morph_116wkg/creature.urdf", "config/morph_116wkg/gains.yaml",
     "config/morph_116wkg/body.yaml", ["--added-mass-products", "omitted"]),
    ("`config/morph_nsga2` (co-evolved by NSGA-II, the sourced motors: front member 21)",
     "config/morph_nsga2/creature.urdf", "config/morph_nsga2/gains.yaml",
     "config/morph_nsga2/body.yaml", ["--added-mass-products", "omitted"]),
    ("`config/morph_light_motors` (co-evolved, 1000 W/kg motors)",
     "config/morph_light_motors/creature.urdf", "config/morph_light_motors/gains.yaml",
     "config/morph_light_motors/body.yaml", ["--added-mass-products", "omitted"]),
    ("`config/morph_kirchhoff` (co-evolved by NSGA-II in Kirchhoff's air: front member 7)",
     "config/morph_kirchhoff/creature.urdf", "config/morph_kirchhoff/gains.yaml",
     "config/morph_kirchhoff/body.yaml", ["--added-mass-products", "kirchhoff"]),
    ("`config/morph_shed` (co-evolved by NSGA-II in the air with the products shed: member 11)",
     "config/morph_shed/creature.urdf", "config/morph_shed/gains.yaml",
     "config/morph_shed/body.yaml", []),
]
BODY_WIDTH = 0.03  # m, every hover body's (make_creature --layout hover)
AIR_VISCOSITY = 1.5e-5  # m^2/s, kinematic


def yaml_numbers(path):
    """{key: number} of a flat YAML map file (comments dropped)."""
    numbers = {}
    with open(os.path.join(ROOT, path)) as f:
        for line in f:
            line = line.split("#")[0]
            if ":" in line:
                k, v = line.split(":", 1)
                numbers[k.strip()] = float(v)
    return numbers


def gallery():
    runs = [Run(label, [FLIGHT_CHECK, "--hover", "--urdf", urdf, "--gains", gains, "--duration",
                        "30"] + air) for label, urdf, gains, _, air in CREATURES]

    def rows(out):
        result = []
        for label, _, gains, body, _ in CREATURES:
            text = out[label]
            r = hover_report(text)
            f = float(re.search(r"([0-9.]+) Hz", text).group(1))
            disk = float(re.search(r"actuator disk of ([0-9.]+) m\^2", text).group(1))
            b = yaml_numbers(body)
            length, chord = b["wing_span"], b["wing_chord"]
            tip = 4 * yaml_numbers(gains)["amplitude"] * f * length  # mean wingtip speed
            result.append([label, f"{r['mass_g']:.1f} g",
                           f"{100 * (2 * length + BODY_WIDTH):.1f} cm", f"{length / chord:.2f}",
                           f"{f:.1f} Hz", f"{tip * chord / AIR_VISCOSITY:,.0f}",
                           f"{r['mass_g'] * 1e-3 * 9.81 / disk:.1f} N/m^2",
                           f"{r['w_per_kg']:.1f} W/kg", f"{r['merit']:.2f}",
                           f"{'yes' if r['pass'] else 'no'}, {1000 * r['rms']:.1f} mm rms"])
        return result
    return Table("morph_gallery", "doc/hovering.md",
                 ["creature", "mass", "span", "aspect ratio", "frequency", "Re", "disk loading",
                  "power", "figure of merit", "holds 3 m"], runs, rows,
                 f"`{FLIGHT_CHECK} --hover --urdf URDF --gains GAINS --duration 30` for each "
                 "(figures after 10 s), in the air each was evolved in (`--added-mass-products "
                 "omitted` or `kirchhoff`; the shed air is the default); the wing's length and chord from its body file "
                 "(`config/hover_1_body.yaml` for hover_1)")


TABLES = [gallery]
