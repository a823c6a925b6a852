"""Low-level probes of the BallBearing FMU through fmpy's FMU2Slave.

Each probe runs in its own process (the pytest side starts `python probes.py NAME FMU_DIR
[ARGS]`), so that a crash of the FMU fails one test instead of killing pytest. A probe prints
one JSON line `RESULT {...}` on stdout; the test inspects it.
"""

import ctypes
import json
import math
import os
import sys
import threading
from ctypes import byref, c_double, c_int, c_uint, c_void_p

from fmpy import calloc, free
from fmpy.fmi2 import (
    FMU2Slave,
    fmi2CallbackAllocateMemoryTYPE,
    fmi2CallbackFreeMemoryTYPE,
    fmi2CallbackFunctions,
    fmi2CallbackLoggerTYPE,
    fmi2CoSimulation,
    fmi2LastSuccessfulTime,
    fmi2Terminated,
)
from fmpy.model_description import read_model_description

try:
    from fmpy.logging import addLoggerProxy
except Exception:  # pragma: no cover - very old fmpy
    addLoggerProxy = None

MESSAGES = []


def _logger(env, name, status, category, message):
    MESSAGES.append((int(status), category.decode(errors="replace"), message.decode(errors="replace")))


def make_callbacks(logger=True):
    cb = fmi2CallbackFunctions()
    if logger:
        cb.logger = fmi2CallbackLoggerTYPE(_logger)
    cb.allocateMemory = fmi2CallbackAllocateMemoryTYPE(calloc)
    cb.freeMemory = fmi2CallbackFreeMemoryTYPE(free)
    if logger and addLoggerProxy is not None:
        addLoggerProxy(byref(cb))  # formats the variadic arguments natively
    return cb


class Ctx:
    def __init__(self, fmu_dir):
        self.dir = fmu_dir
        # Coupling mode of the probes (0 force, 1 motion): RACEWAY_PROBE_COUPLING, set by the
        # tests parametrized over both modes.
        self.coupling = int(os.environ.get("RACEWAY_PROBE_COUPLING", "0"))
        self.md = read_model_description(os.path.join(fmu_dir, "modelDescription.xml"))
        self.vr = {v.name: v.valueReference for v in self.md.modelVariables}
        self.var = {v.name: v for v in self.md.modelVariables}
        self.real_outputs = [v.valueReference for v in self.md.modelVariables
                             if v.causality == "output" and v.type == "Real"]
        self.int_outputs = [v.valueReference for v in self.md.modelVariables
                            if v.causality == "output" and v.type == "Integer"]
        self.callbacks = make_callbacks()

    def slave(self, name="probe", guid=None):
        return FMU2Slave(guid=guid or self.md.guid, unzipDirectory=self.dir,
                         modelIdentifier="BallBearing", instanceName=name)

    def new(self, name="probe", logging=True, guid=None):
        s = self.slave(name, guid)
        s.instantiate(callbacks=self.callbacks, loggingOn=logging)
        self.configure(s)
        return s

    def configure(self, s):
        """Sets the probe's coupling mode (again after fmi2Reset, which restores the starts)."""
        if self.coupling:
            s.setInteger([self.vr["coupling"]], [self.coupling])

    def ready(self, name="probe", params=None, ints=None, stop=None, tol=1e-6):
        s = self.new(name, logging=False)
        s.setupExperiment(tolerance=tol, startTime=0.0, stopTime=stop)
        for k, v in (params or {}).items():
            s.setReal([self.vr[k]], [v])
        for k, v in (ints or {}).items():
            s.setInteger([self.vr[k]], [v])
        s.enterInitializationMode()
        s.exitInitializationMode()
        return s

    def outputs(self, s):
        return list(s.getReal(self.real_outputs)) + [float(x) for x in s.getInteger(self.int_outputs)]


def status_of(f, *args):
    """Calls an fmpy wrapper; returns the FMI status (0 when it did not raise)."""
    try:
        f(*args)
        return 0
    except Exception as e:  # fmpy raises FMICallException for status > fmi2Warning
        return int(getattr(e, "status", -1))


def last_message():
    return MESSAGES[-1][2] if MESSAGES else ""


def run(ctx, s, t0, h, n, record=True):
    rows = []
    t = t0
    for k in range(n):
        s.doStep(currentCommunicationPoint=t, communicationStepSize=h)
        t = t0 + (k + 1) * h
        if record:
            rows.append(ctx.outputs(s))
    return t, rows


# --- probes -------------------------------------------------------------------------------------

def probe_advance_check(ctx):
    s = ctx.ready()
    st = status_of(s.doStep, 0.0, 1e-4)
    return {"ok": st == 0, "status": st, "message": last_message()}


def probe_enumeration(ctx):
    """The mode switches are Enumerations: each takes its items through fmi2SetInteger and reads
    them back through fmi2GetInteger; a value that is no item is refused with a message; the
    Real functions refuse them."""
    s = ctx.new(logging=False)
    s.setupExperiment(tolerance=1e-6, startTime=0.0)
    s.enterInitializationMode()  # fixed parameters are set and read there too
    out = {}
    for v in ctx.md.modelVariables:
        if v.type != "Enumeration":
            continue
        values = sorted(int(i.value) for i in v.declaredType.items)
        bad = [status_of(s.setInteger, [v.valueReference], [values[-1] + 1]), last_message()]
        got = []
        for x in values:
            st = status_of(s.setInteger, [v.valueReference], [x])
            got.append([st, int(s.getInteger([v.valueReference])[0])])
        out[v.name] = {"values": values, "bad": bad, "got": got}
    out["get_real"] = [status_of(s.getReal, [ctx.vr["fidelity"]]), last_message()]
    return out


def probe_wrong_guid(ctx):
    s = ctx.slave(guid="{00000000-0000-0000-0000-000000000000}")
    try:
        s.instantiate(callbacks=ctx.callbacks)
        return {"null": False}
    except Exception as e:
        return {"null": True, "error": str(e), "message": last_message()}


def probe_null_logger(ctx):
    s = ctx.slave()
    cb = make_callbacks(logger=False)
    try:
        s.instantiate(callbacks=cb)
        return {"null": False}
    except Exception as e:
        return {"null": True, "error": str(e)}


def probe_bad_order(ctx):
    s = ctx.new()
    st = status_of(s.doStep, 0.0, 1e-4)
    msg = last_message()
    st_get = status_of(s.getReal, [ctx.real_outputs[0]])
    st_exit = status_of(s.exitInitializationMode)
    # the rejected calls had no effect: the normal sequence still works
    s.setupExperiment(tolerance=1e-6, startTime=0.0)
    s.enterInitializationMode()
    s.exitInitializationMode()
    st_init = status_of(s.enterInitializationMode)
    return {"doStep": st, "message": msg, "getReal": st_get, "exit": st_exit, "enterAgain": st_init}


def probe_step_args(ctx):
    s = ctx.ready(stop=0.1)
    out = {}
    for key, (t, h) in {"zero": (0.0, 0.0), "negative": (0.0, -1e-4), "nan": (0.0, float("nan")),
                        "wrong_time": (0.5, 1e-4), "past_stop": (0.0, 0.2)}.items():
        out[key] = [status_of(s.doStep, t, h), last_message()]
    return out


def probe_nan_input(ctx):
    s = ctx.new()
    out = {}
    for name in ["load.Fx", "shaft.speed"]:
        out[name] = [status_of(s.setReal, [ctx.vr[name]], [float("nan")]), last_message()]
    out["inf_param"] = [status_of(s.setReal, [ctx.vr["pedestal.mass"]], [float("inf")]), last_message()]
    out["range"] = [status_of(s.setReal, [ctx.vr["lumped.slip_jitter"]], [0.7]), last_message()]
    out["output"] = [status_of(s.setReal, [ctx.vr["pedestal.a.z"]], [1.0]), last_message()]
    s.setupExperiment(tolerance=1e-6, startTime=0.0)
    s.enterInitializationMode()
    # The refused variables still hold their earlier values: initialization refuses to run on
    # them until they are set again.
    out["exit_refused"] = [status_of(s.exitInitializationMode), last_message()]
    for name in ["load.Fx", "shaft.speed", "pedestal.mass", "lumped.slip_jitter"]:
        s.setReal([ctx.vr[name]], [float(ctx.var[name].start)])
    s.exitInitializationMode()
    out["fixed_after_init"] = [status_of(s.setReal, [ctx.vr["pedestal.mass"]], [1.0]), last_message()]
    out["nan_after_init"] = [status_of(s.setReal, [ctx.vr["load.Fz"]], [float("nan")]), last_message()]
    out["ok_input"] = [status_of(s.setReal, [ctx.vr["load.Fz"]], [-1200.0]), ""]
    return out


def probe_bad_parameter(ctx):
    """Impossible geometry / cross-field rules are reported at fmi2ExitInitializationMode."""
    s = ctx.new()
    s.setupExperiment(tolerance=1e-6, startTime=0.0)
    s.setReal([ctx.vr["traction.kappa_0"]], [0.5])  # > kappa_max
    s.enterInitializationMode()
    st = status_of(s.exitInitializationMode)
    return {"status": st, "message": last_message()}


def probe_unsupported_fidelity(ctx):
    res = {}
    for code in range(5):
        s = ctx.new(name=f"f{code}")
        s.setupExperiment(tolerance=1e-6, startTime=0.0)
        s.setInteger([ctx.vr["fidelity"]], [code])
        s.enterInitializationMode()
        st = status_of(s.exitInitializationMode)
        res[str(code)] = [st, last_message() if st else ""]
        s.fmi2FreeInstance(s.component)
    return res


def probe_unknown_vr(ctx):
    s = ctx.ready()
    st = status_of(s.getReal, [99999])
    msg = last_message()
    st_type = status_of(s.getInteger, [ctx.vr["pedestal.a.z"]])
    return {"status": st, "message": msg, "wrong_type": st_type, "type_message": last_message()}


def probe_unknown_category(ctx):
    s = ctx.new()
    st = status_of(s.setDebugLogging, True, ["logNoSuchThing"])
    msg = last_message()
    ok = status_of(s.setDebugLogging, True, ["logEvents", "logSolver"])
    return {"status": st, "message": msg, "valid": ok}


def probe_reset_rerun(ctx, n=300):
    s = ctx.ready()
    _, a = run(ctx, s, 0.0, 1e-4, n)
    s.terminate()
    s.reset()
    ctx.configure(s)
    s.setupExperiment(tolerance=1e-6, startTime=0.0)
    s.enterInitializationMode()
    s.exitInitializationMode()
    _, b = run(ctx, s, 0.0, 1e-4, n)
    # reset after an error too
    st = status_of(s.doStep, 5.0, 1e-4)
    s.reset()
    ctx.configure(s)
    s.setupExperiment(tolerance=1e-6, startTime=0.0)
    s.enterInitializationMode()
    s.exitInitializationMode()
    _, c = run(ctx, s, 0.0, 1e-4, n)
    return {"equal": a == b, "equal_after_error": a == c, "error_status": st}


def probe_state_getset(ctx, blob_path, n=200):
    s = ctx.ready()
    if ctx.coupling:
        # a moving journal: its position, velocity and set time are part of the state
        s.setReal([ctx.vr["journal.v.z"], ctx.vr["journal.v.x"]], [-1e-4, 5e-5])
    t, _ = run(ctx, s, 0.0, 1e-4, n, record=False)
    state = s.getFMUstate()
    _, a = run(ctx, s, t, 1e-4, n)
    s.setFMUstate(state)
    _, b = run(ctx, s, t, 1e-4, n)
    blob = s.serializeFMUstate(state)
    s.freeFMUstate(state)
    with open(blob_path, "wb") as f:
        f.write(bytes(blob))
    with open(blob_path + ".json", "w") as f:
        json.dump({"t": t, "a": a}, f)
    # a truncated and a corrupted blob are errors, not crashes
    st_trunc = status_of(s.deSerializeFMUstate, bytes(blob)[: len(blob) // 2])
    bad = bytearray(bytes(blob))
    bad[len(bad) // 3] ^= 0xFF
    st_bad = status_of(s.deSerializeFMUstate, bytes(bad))
    st_foreign = status_of(s.deSerializeFMUstate, b"\x00" * 64)
    return {"equal": a == b, "size": len(blob), "truncated": st_trunc, "corrupt": st_bad,
            "foreign": st_foreign}


def probe_state_restore(ctx, blob_path):
    with open(blob_path, "rb") as f:
        blob = f.read()
    with open(blob_path + ".json") as f:
        saved = json.load(f)
    s = ctx.new(logging=False)  # a fresh process and a fresh, uninitialized instance
    state = s.deSerializeFMUstate(blob)
    s.setFMUstate(state)
    s.freeFMUstate(state)
    _, c = run(ctx, s, saved["t"], 1e-4, len(saved["a"]))
    return {"equal": c == saved["a"]}


def _scenario(i, ctx=None):
    if ctx is not None and ctx.coupling:
        # motion mode ignores the loads after the start: move the journal instead
        return {"journal.v.z": -1e-4 * (i + 1), "journal.v.y": 5e-5 * i}
    return {"load.Fz": -1000.0 - 100.0 * i, "load.Fx": 4000.0 + 50.0 * i}


def _solo(ctx, i, n, name):
    s = ctx.ready(name=name)
    s.setReal([ctx.vr[k] for k in _scenario(i, ctx)], list(_scenario(i, ctx).values()))
    _, r = run(ctx, s, 0.0, 1e-4, n)
    s.terminate()
    s.fmi2FreeInstance(s.component)
    return r


def probe_interleaved(ctx, n=200):
    solo = [_solo(ctx, i, n, f"solo{i}") for i in range(2)]
    insts = []
    for i in range(2):
        s = ctx.ready(name=f"inter{i}")
        s.setReal([ctx.vr[k] for k in _scenario(i, ctx)], list(_scenario(i, ctx).values()))
        insts.append(s)
    rows = [[], []]
    for k in range(n):
        for i, s in enumerate(insts):
            s.doStep(currentCommunicationPoint=k * 1e-4, communicationStepSize=1e-4)
            rows[i].append(ctx.outputs(s))
    return {"equal": [rows[i] == solo[i] for i in range(2)], "differ": solo[0] != solo[1]}


def probe_threads(ctx, n=200, nthreads=8):
    serial = [_solo(ctx, i, n, f"serial{i}") for i in range(nthreads)]
    results = [None] * nthreads
    errors = []
    comps = [ctx.new(name=f"thread{i}", logging=False) for i in range(nthreads)]  # made here

    def work(i):
        try:
            s = comps[i]
            s.setupExperiment(tolerance=1e-6, startTime=0.0)
            s.enterInitializationMode()
            s.exitInitializationMode()
            s.setReal([ctx.vr[k] for k in _scenario(i, ctx)], list(_scenario(i, ctx).values()))
            _, results[i] = run(ctx, s, 0.0, 1e-4, n)
        except Exception as e:  # pragma: no cover - reported
            errors.append(repr(e))

    threads = [threading.Thread(target=work, args=(i,)) for i in range(nthreads)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    for s in comps:  # freed on a third thread context: the main one
        s.fmi2FreeInstance(s.component)
    return {"equal": [results[i] == serial[i] for i in range(nthreads)], "errors": errors}


def _rss_kib():
    with open("/proc/self/status") as f:
        for line in f:
            if line.startswith("VmRSS:"):
                return int(line.split()[1])
    return 0


def probe_memory(ctx, cycles=1000):
    s = ctx.slave()
    inst = s.fmi2Instantiate
    guid = ctx.md.guid.encode()
    uri = ("file://" + os.path.join(ctx.dir, "resources")).encode()

    def cycle():
        c = inst(b"mem", fmi2CoSimulation, guid, uri, byref(ctx.callbacks), 0, 0)
        if not c:
            raise RuntimeError("instantiate returned NULL: " + last_message())
        s.fmi2SetupExperiment(c, 1, 1e-6, 0.0, 0, 0.0)
        s.fmi2EnterInitializationMode(c)
        s.fmi2ExitInitializationMode(c)
        s.fmi2FreeInstance(c)

    for _ in range(100):
        cycle()
    before = _rss_kib()
    for _ in range(cycles):
        cycle()
    after = _rss_kib()
    return {"before_kib": before, "after_kib": after, "growth_kib": after - before}


def probe_forced_failure(ctx):
    s = ctx.ready(ints={"solver.max_steps": 1})
    t = 0.0
    st = 0
    n_ok = 0
    for k in range(100):
        before = ctx.outputs(s)
        st = status_of(s.doStep, t, 1e-3)
        if st != 0:
            break
        n_ok += 1
        t = (k + 1) * 1e-3
    msg = last_message()
    level = MESSAGES[-1][0] if MESSAGES else -1
    terminated = s.getBooleanStatus(fmi2Terminated)
    last = s.getRealStatus(fmi2LastSuccessfulTime)
    after = ctx.outputs(s)
    st_next = status_of(s.doStep, t, 1e-3)
    finite = all(math.isfinite(x) for x in s.getReal(ctx.real_outputs))
    s.terminate()
    return {"status": st, "message": msg, "logged_status": level, "terminated": bool(terminated),
            "last": last, "t_before": t, "steps_ok": n_ok, "next": st_next, "finite": finite,
            "same_outputs": after == before}


def probe_step_invariance(ctx, t_end=0.02):
    """Outputs at common 1 ms points for h = 1e-4, 1e-3 and an irregular sequence."""
    names = ["pedestal.a.z", "pedestal.z", "ring.z", "bearing.F.z", "cage.speed"]
    vrs = [ctx.vr[n] for n in names]
    grid = [round(1e-3 * k, 12) for k in range(1, int(round(t_end / 1e-3)) + 1)]

    def sample_run(steps):
        s = ctx.ready()
        t = 0.0
        out = {}
        for h in steps:
            s.doStep(currentCommunicationPoint=t, communicationStepSize=h)
            t = t + h
            key = round(t, 12)
            if key in grid:
                out[key] = list(s.getReal(vrs))
        return [out[g] for g in grid]

    fine = sample_run([1e-4] * int(round(t_end / 1e-4)))
    coarse = sample_run([1e-3] * int(round(t_end / 1e-3)))
    # irregular: each millisecond split as 0.1 + 0.25 + 0.05 + 0.6 ms
    irregular = sample_run([1e-4, 2.5e-4, 5e-5, 6e-4] * int(round(t_end / 1e-3)))
    return {"names": names, "fine": fine, "coarse": coarse, "irregular": irregular}


def probe_reduced_level(ctx, n=20, h=1e-4):
    """fidelity = 3 (reduced) through the FMU: per-ball orbital speeds and separation flags."""
    s = ctx.ready(ints={"fidelity": 3})
    z = sum(1 for name in ctx.vr if name.startswith("contact.inner.Q["))
    names = ["cage.speed"] + [f"ball.orbit_speed[{j}]" for j in range(1, z + 1)] + \
        [f"ball.separated[{j}]" for j in range(1, z + 1)] + \
        [f"contact.{r}.Q[{j}]" for r in ("inner", "outer") for j in range(1, z + 1)]
    vrs = [ctx.vr[x] for x in names]
    rows, t = [], 0.0
    for k in range(n):
        st = status_of(s.doStep, t, h)
        if st:
            return {"status": st, "message": last_message()}
        t += h
        rows.append(list(s.getReal(vrs)))
    return {"status": 0, "z": z, "names": names, "rows": rows}


def _journal_vrs(ctx):
    return [ctx.vr[n] for n in ["journal.x", "journal.y", "journal.z",
                                "journal.v.x", "journal.v.y", "journal.v.z"]]


def probe_motion_basics(ctx, fidelity=2):
    """Motion mode: the start is the static equilibrium under the loads; the ring follows the
    journal; the loads are ignored after the start; a NaN journal input is rejected."""
    fidelity = int(fidelity)
    s = ctx.new(logging=True)
    s.setInteger([ctx.vr["coupling"], ctx.vr["fidelity"]], [1, fidelity])
    s.setupExperiment(tolerance=1e-6, startTime=0.0)
    s.enterInitializationMode()
    f_vr = [ctx.vr[n] for n in ["bearing.F.x", "bearing.F.y", "bearing.F.z"]]
    r_vr = [ctx.vr[n] for n in ["ring.x", "ring.y", "ring.z"]]
    load = list(s.getReal([ctx.vr[n] for n in ["load.Fx", "load.Fy", "load.Fz"]]))
    ring_init = list(s.getReal(r_vr))
    force_init = list(s.getReal(f_vr))
    s.exitInitializationMode()
    journal0 = list(s.getReal(_journal_vrs(ctx)))
    ring0 = list(s.getReal(r_vr))
    # hold the journal: move it by a velocity over one step
    v = [0.0, 1e-4, -2e-4]
    s.setReal(_journal_vrs(ctx)[3:], v)
    h = 1e-4
    s.doStep(currentCommunicationPoint=0.0, communicationStepSize=h)
    ring1 = list(s.getReal(r_vr))
    f1 = list(s.getReal(f_vr))
    st_load = status_of(s.setReal, [ctx.vr["load.Fz"]], [-3000.0])
    f1b = list(s.getReal(f_vr))
    st_nan = status_of(s.setReal, [ctx.vr["journal.z"]], [float("nan")])
    nan_msg = last_message()
    return {"load": load, "ring_init": ring_init, "force_init": force_init,
            "journal0": journal0, "ring0": ring0, "ring1": ring1, "v": v, "h": h,
            "f1": f1, "f1_after_load": f1b, "load_status": st_load,
            "nan_status": st_nan, "nan_message": nan_msg}


def probe_directional(ctx, fidelity=2, steps=30):
    """fmi2GetDirectionalDerivative of bearing.F.* w.r.t. journal.* against central
    differences of bearing.F (journal moved and restored at the same communication point)."""
    fidelity = int(fidelity)
    s = ctx.new(logging=True)
    s.setInteger([ctx.vr["coupling"], ctx.vr["fidelity"]], [1, fidelity])
    s.setupExperiment(tolerance=1e-6, startTime=0.0)
    s.enterInitializationMode()
    s.exitInitializationMode()
    jv = _journal_vrs(ctx)
    f_vr = [ctx.vr[n] for n in ["bearing.F.x", "bearing.F.y", "bearing.F.z"]]
    t = 0.0
    h = 2e-5
    s.setReal(jv[3:], [1e-4, -1e-4, 2e-4])
    for _ in range(int(steps)):
        s.doStep(currentCommunicationPoint=t, communicationStepSize=h)
        t += h
    # at t: set the journal to where the ring is now (x_k + v_k h), keeping the velocity, so
    # that the linearization point is the finite differences' centre
    r_vr = [ctx.vr[n] for n in ["ring.x", "ring.y", "ring.z"]]
    s.setReal(jv[:3], list(s.getReal(r_vr)))
    j0 = list(s.getReal(jv))
    analytic = []
    for k in range(6):
        seed = [0.0] * 6
        seed[k] = 1.0
        analytic.append(list(s.getDirectionalDerivative(f_vr, jv, seed)))
    fd = []
    for k in range(6):
        step = 1e-9 if k < 3 else 1e-4
        cols = []
        for sign in (1.0, -1.0):
            j = list(j0)
            j[k] += sign * step
            s.setReal(jv, j)
            cols.append(list(s.getReal(f_vr)))
        s.setReal(jv, j0)
        fd.append([(cols[0][i] - cols[1][i]) / (2 * step) for i in range(3)])
    q = [ctx.vr[f"contact.inner.Q[{j}]"] for j in range(1, 15)]
    qmin = min(s.getReal(q))
    ring = list(s.getReal([ctx.vr[n] for n in ["ring.x", "ring.y", "ring.z"]]))
    d_ring = list(s.getDirectionalDerivative([ctx.vr["ring.z"]], jv, [0, 0, 1, 0, 0, 0]))
    # force mode refuses
    s2 = ctx.new(name="force", logging=True)
    s2.setInteger([ctx.vr["coupling"]], [0])
    s2.setupExperiment(tolerance=1e-6, startTime=0.0)
    s2.enterInitializationMode()
    s2.exitInitializationMode()
    st_force = status_of(s2.getDirectionalDerivative, f_vr, jv, [1, 0, 0, 0, 0, 0])
    force_msg = last_message()
    # wrong causalities and pairs that are not provided are errors naming the variables
    st_in = status_of(s.getDirectionalDerivative, [jv[0]], jv, [1, 0, 0, 0, 0, 0])
    msg_in = last_message()
    st_out = status_of(s.getDirectionalDerivative, f_vr, [f_vr[0]], [1.0])
    msg_out = last_message()
    st_pair = status_of(s.getDirectionalDerivative, [ctx.vr["contact.inner.Q[1]"]], jv[:1], [1.0])
    msg_pair = last_message()
    return {"in_status": st_in, "in_message": msg_in, "out_status": st_out,
            "out_message": msg_out, "pair_status": st_pair, "pair_message": msg_pair,"analytic": analytic, "fd": fd, "qmin": qmin, "ring": ring, "journal": j0,
            "d_ring": d_ring, "force_status": st_force, "force_message": force_msg}


def main():
    name, fmu_dir, *args = sys.argv[1:]
    ctx = Ctx(fmu_dir)
    result = globals()["probe_" + name](ctx, *args)
    result["log"] = [m[2] for m in MESSAGES[-20:]]
    print("RESULT " + json.dumps(result))
    sys.stdout.flush()


if __name__ == "__main__":
    main()
