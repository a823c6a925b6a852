"""Packs the rotor <-> bearing SSP 1.0 system from the built FMUs.

Usage: python examples/systems/build_ssp.py [--out <target>/fmu/RotorBearing.ssp]
                                            [--write-ssd]

The system (examples/systems/rotor_bearing/SystemStructure.ssd, committed) couples the
JeffcottRotor FMU to the BallBearing FMU in motion mode (coupling = 1):

    rotor.journal.x/y/z, rotor.journal.v.x/y/z -> bearing.journal.x/y/z, bearing.journal.v.x/y/z
    rotor.shaft.speed                          -> bearing.shaft.speed
    bearing.bearing.F.x/y/z                    -> rotor.bearing.F.x/y/z

and runs the rotor up through its first critical speed (speed ramp inside the rotor). Parameter
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
from cosim_master import fmu_path  # noqa: E402

SSD = HERE / "rotor_bearing" / "SystemStructure.ssd"
AXES = ("x", "y", "z")

# Run-up: 2400 -> 8100 rpm at 600 rad/s^2 (0.99 s), through the first critical speed (~4.6k rpm).
RUNUP = {"speed.initial": 250.0, "speed.final": 850.0, "speed.rate": 600.0}
STEP = 1e-5  # master step [s]: explicit coupling needs omega*H < 4 zeta (docs/coupling.md)
STOP = 1.1
# The journal's damper (squeeze film) gives the journal-on-bearing mode zeta ~ 0.1, which makes
# the explicit coupling of plain SSP masters stable at STEP (limit ~ 50 us).
# shaft.c = 400 N s/m: disk mode zeta ~ 0.05, so start transients (fmpy's zero first step) die
# within ~0.1 s and the resonance stays sharp enough for the run-up plot.
ROTOR = {"journal.c": 3000.0, "shaft.c": 400.0, "unbalance": 1e-4, **RUNUP}
# Motion mode; the start loads (the rotor's load and weight: 10 kg) and speed put the bearing's
# start equilibrium where the rotor's journal starts (statics.py).
BEARING = {"coupling": 1, "shaft.speed": RUNUP["speed.initial"], "load.Fx": 4000.0,
           "load.Fy": 0.0, "load.Fz": -1000.0 - 10.0 * 9.81}
# Connections (start element, start connector, end element, end connector).
CONNECTIONS = (
    [("rotor", f"journal.{a}", "bearing", f"journal.{a}") for a in AXES]
    + [("rotor", f"journal.v.{a}", "bearing", f"journal.v.{a}") for a in AXES]
    + [("rotor", "shaft.speed", "bearing", "shaft.speed")]
    + [("bearing", f"bearing.F.{a}", "rotor", f"bearing.F.{a}") for a in AXES]
)
# Extra outputs recorded (connectors without connections).
EXTRA = {
    "rotor": ["disk.y", "disk.z", "shaft.angle"],
    "bearing": ["pedestal.a.z", "ring.z", "cage.speed"],
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
<!-- Rotor <-> ball bearing, motion-mode coupling; packed by examples/systems/build_ssp.py -->
<ssd:SystemStructureDescription version="1.0" name="RotorBearing"
    xmlns:ssc="http://ssp-standard.org/SSP1/SystemStructureCommon"
    xmlns:ssd="http://ssp-standard.org/SSP1/SystemStructureDescription"
    xmlns:ssv="http://ssp-standard.org/SSP1/SystemStructureParameterValues">
  <ssd:System name="RotorBearing" description="Jeffcott rotor run-up on a spalled angular-contact ball bearing (BallBearing in motion mode)">
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
