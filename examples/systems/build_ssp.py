"""Packs the rotor <-> bearing SSP 1.0 system from the built FMUs.

Usage: python examples/systems/build_ssp.py [--out <target>/fmu/RotorBearing.ssp]
                                            [--write-ssd]

The system (examples/systems/rotor_bearing/SystemStructure.ssd, committed) couples the
JeffcottRotor FMU to the BallBearing FMU through a transmission line (TLM) in the shaft: the
rotor (coupling = 1) keeps the disk and simulates the shaft as a line of delay tlm.delay = the
communication step; the bearing (coupling = 2) holds the journal's mass (its inner ring):

    rotor.tlm.c0.y/z, tlm.c1.y/z, tlm.Zc -> bearing.tlm.c0.y/z, tlm.c1.y/z, tlm.Zc
    bearing.ring.v.y/z                    -> rotor.tlm.v.y/z
    rotor.shaft.speed                     -> bearing.shaft.speed

and runs the rotor up through its first critical speed (speed ramp inside the rotor), without
any added damper, at a communication step of 0.1 ms. The line is passive, so plain value
exchange (libcosim, fmpy) is stable at every step; neither FMU's outputs depend on its inputs at
the same instant, so the order in which a master sets and reads them does not matter. Parameter
values are inline ParameterBindings of each component (SSP 1.0, ssv:ParameterSet).

--write-ssd regenerates the committed SystemStructure.ssd from SYSTEM below (the initial journal
position is the bearing's static displacement from `raceway static --json`, see
examples/systems/statics.py); without it the committed file is packed as it is, with
resources/JeffcottRotor.fmu and resources/BallBearing.fmu from <target>/fmu/.
"""

import argparse
import pathlib
import sys
import zipfile
from xml.sax.saxutils import quoteattr

HERE = pathlib.Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent))
from cosim_master import fmu_path, half_ball_mass  # noqa: E402

SSD = HERE / "rotor_bearing" / "SystemStructure.ssd"
AXES = ("x", "y", "z")

# Run-up: 2400 -> 8100 rpm at 600 rad/s^2 (0.99 s), through the first critical speed (~4.7k rpm).
RUNUP = {"speed.initial": 250.0, "speed.final": 850.0, "speed.rate": 600.0}
STEP = 1e-4  # master step [s]: the line's delay (tlm.delay) must equal it
STOP = 1.1
JOURNAL_MASS = 2.0  # kg: the rotor's default journal mass, now the bearing's ring mass
G = 9.81
# shaft.c = 400 N s/m: disk mode zeta ~ 0.05, so start transients die within ~0.1 s and the
# resonance stays sharp enough for the run-up plot. The rotor's own load and journal parameters
# do not act in tlm mode (the journal is the bearing's): its load goes to the bearing.
ROTOR = {"coupling": 1, "tlm.delay": STEP, "shaft.c": 400.0, "unbalance": 1e-4, "load.Fx": 0.0,
         "load.Fz": 0.0, **RUNUP}
# tlm mode: the journal's load and weight act on the bearing's ring, whose mass is the journal's
# (at the default lumped level the ring carries half the balls: inner_ring.mass is the rest);
# the disk's weight comes through the line.
BEARING = {"coupling": 2, "shaft.speed": RUNUP["speed.initial"], "load.Fx": 4000.0,
           "load.Fy": 0.0, "load.Fz": -1000.0 - JOURNAL_MASS * G,
           "inner_ring.mass": JOURNAL_MASS - half_ball_mass()}
# Connections (start element, start connector, end element, end connector).
LINE = ["tlm.c0.y", "tlm.c0.z", "tlm.c1.y", "tlm.c1.z", "tlm.Zc"]
CONNECTIONS = (
    [("rotor", n, "bearing", n) for n in LINE]
    + [("bearing", f"ring.v.{a}", "rotor", f"tlm.v.{a}") for a in ("y", "z")]
    + [("rotor", "shaft.speed", "bearing", "shaft.speed")]
)
# Extra outputs recorded (connectors without connections).
EXTRA = {
    "rotor": ["disk.y", "disk.z", "shaft.angle"],
    "bearing": ["bearing.F.z", "pedestal.a.z", "ring.y", "ring.z", "cage.speed"],
}


def ssd_text(journal0):
    rotor_params = {**ROTOR, **{f"journal.{a}0": v for a, v in zip(AXES, journal0)}}
    conns = {"rotor": [], "bearing": []}
    for se, sc, ee, ec in CONNECTIONS:
        conns[se].append((sc, "output"))
        conns[ee].append((ec, "input"))
    for el, names in EXTRA.items():
        conns[el] += [(n, "output") for n in names]

    def params_xml(name, params):
        lines = []
        for k, v in params.items():
            kind = "Integer" if isinstance(v, int) else "Real"
            lines.append(f'                <ssv:Parameter name={quoteattr(k)}><ssv:{kind} value="{v!r}"/></ssv:Parameter>')
        return "\n".join([
            "        <ssd:ParameterBindings>",
            "          <ssd:ParameterBinding>",
            "            <ssd:ParameterValues>",
            f'              <ssv:ParameterSet version="1.0" name="{name}">',
            "                <ssv:Parameters>",
            *lines,
            "                </ssv:Parameters>",
            "              </ssv:ParameterSet>",
            "            </ssd:ParameterValues>",
            "          </ssd:ParameterBinding>",
            "        </ssd:ParameterBindings>",
        ])

    def component(name, fmu, params):
        cs = "\n".join(
            f'          <ssd:Connector name={quoteattr(n)} kind="{k}"><ssc:Real/></ssd:Connector>'
            for n, k in conns[name])
        return (f'      <ssd:Component name="{name}" type="application/x-fmu-sharedlibrary" '
                f'source="resources/{fmu}.fmu">\n        <ssd:Connectors>\n{cs}\n'
                f'        </ssd:Connectors>\n{params_xml(name, params)}\n      </ssd:Component>')

    connections = "\n".join(
        f'      <ssd:Connection startElement="{se}" startConnector={quoteattr(sc)} '
        f'endElement="{ee}" endConnector={quoteattr(ec)}/>'
        for se, sc, ee, ec in CONNECTIONS)
    return f"""<?xml version="1.0" encoding="UTF-8"?>
<!-- Rotor <-> ball bearing through a transmission line in the shaft; packed by examples/systems/build_ssp.py -->
<ssd:SystemStructureDescription version="1.0" name="RotorBearing"
    xmlns:ssc="http://ssp-standard.org/SSP1/SystemStructureCommon"
    xmlns:ssd="http://ssp-standard.org/SSP1/SystemStructureDescription"
    xmlns:ssv="http://ssp-standard.org/SSP1/SystemStructureParameterValues">
  <ssd:System name="RotorBearing" description="Jeffcott rotor run-up on a spalled angular-contact ball bearing (transmission-line coupling, no added damper)">
    <ssd:Elements>
{component("rotor", "JeffcottRotor", rotor_params)}
{component("bearing", "BallBearing", BEARING)}
    </ssd:Elements>
    <ssd:Connections>
{connections}
    </ssd:Connections>
  </ssd:System>
  <ssd:DefaultExperiment startTime="0.0" stopTime="{STOP!r}"/>
</ssd:SystemStructureDescription>
"""


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", default=str(fmu_path("BallBearing").parent / "RotorBearing.ssp"))
    ap.add_argument("--write-ssd", action="store_true")
    ap.add_argument("--ssd", default=str(SSD), help="pack this SystemStructure.ssd instead")
    a = ap.parse_args()
    if a.write_ssd:
        from statics import journal_equilibrium

        # the rotor reports the journal as seen through the line from journal0: start it
        # where the bearing's start equilibrium puts the ring
        x0 = journal_equilibrium(speed=RUNUP["speed.initial"])
        SSD.parent.mkdir(parents=True, exist_ok=True)
        SSD.write_text(ssd_text(x0))
        print(f"wrote {SSD} (journal start {x0})")
    out = pathlib.Path(a.out)
    out.parent.mkdir(parents=True, exist_ok=True)
    with zipfile.ZipFile(out, "w", zipfile.ZIP_DEFLATED) as z:
        z.write(SSD if a.write_ssd else a.ssd, "SystemStructure.ssd")
        for name in ("JeffcottRotor", "BallBearing"):
            p = fmu_path(name)
            if not p.is_file():
                sys.exit(f"{p} does not exist: build it with `cargo run --release -p fmu-build`")
            z.write(p, f"resources/{name}.fmu")
    print(f"wrote {out}")


if __name__ == "__main__":
    main()
