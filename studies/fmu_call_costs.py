"""What the BallBearing FMU's calls cost through fmpy (median of repeats, this machine):
fmi2Instantiate, initialization, one 0.1 ms fmi2DoStep at the default (lumped) level, and
fmi2SetFMUstate of a state got earlier (what a master that retries steps pays each step).

    cargo run --release -p fmu-build && .venv/bin/python studies/fmu_call_costs.py [FMU]
"""

import statistics
import sys
import time
from pathlib import Path

from fmpy import extract, read_model_description
from fmpy.fmi2 import FMU2Slave

REPO = Path(__file__).resolve().parents[1]


def main():
    fmu = sys.argv[1] if len(sys.argv) > 1 else str(REPO / "target/fmu/BallBearing.fmu")
    md = read_model_description(fmu)
    d = extract(fmu)
    cost = {"fmi2Instantiate": [], "initialization": [], "fmi2DoStep (0.1 ms)": [],
            "fmi2SetFMUstate": []}
    for k in range(5):
        s = FMU2Slave(guid=md.guid, unzipDirectory=d,
                      modelIdentifier=md.coSimulation.modelIdentifier, instanceName=f"i{k}")
        t0 = time.perf_counter()
        s.instantiate()
        t1 = time.perf_counter()
        s.setupExperiment(startTime=0)
        s.enterInitializationMode()
        s.exitInitializationMode()
        t2 = time.perf_counter()
        for n in range(20):
            s.doStep(n * 1e-4, 1e-4)
        t3 = time.perf_counter()
        state = s.getFMUstate()
        t4 = time.perf_counter()
        for _ in range(20):
            s.setFMUstate(state)
        t5 = time.perf_counter()
        s.freeFMUstate(state)
        s.terminate()
        s.freeInstance()
        cost["fmi2Instantiate"].append(t1 - t0)
        cost["initialization"].append(t2 - t1)
        cost["fmi2DoStep (0.1 ms)"].append((t3 - t2) / 20)
        cost["fmi2SetFMUstate"].append((t5 - t4) / 20)
    print(f"{fmu}: median of 5 instances")
    for name, v in cost.items():
        print(f"  {name:22s} {1e3 * statistics.median(v):8.3f} ms")


if __name__ == "__main__":
    main()
