//! `documentation/index.html` of the FMU, generated from the variable table.

use crate::base::{Base, SCENE_RESOURCE};
use crate::variables::{enumerations, table_for, Access, Config, SPALL_SLOTS};
use fmi2::xml::esc;
use fmi2::{Start, VarType};
use raceway::models::{level, LEVELS};
use raceway::{BearingFile, Fidelity, Simulation};

/// Whether each fidelity level runs in this build: (level, availability text). A level is
/// "available" when a simulation of the FMU's base scene (the default scene on its bearing, or
/// its scene resource) at that level can be built and advanced by 0.1 ms; otherwise the
/// library's message is shown (a spall on a ball at the quasi-static level, waviness at the
/// kinematic one, ...).
pub fn fidelity_availability(base: &Base) -> Vec<(Fidelity, Result<(), String>)> {
    LEVELS
        .iter()
        .map(|l| {
            let f = l.fidelity;
            let mut cfg = Config::from_scene(&base.scene);
            cfg.scene.fidelity = f;
            let r = Simulation::new(&cfg.scene_with_spalls())
                .and_then(|mut s| s.advance(1e-4))
                .map_err(|e| e.to_string());
            (f, r)
        })
        .collect()
}

/// The Model Exchange section: what is supported, the padded states and indicators, events,
/// inputs in continuous time.
fn model_exchange_html(bearing: &BearingFile) -> String {
    let z = bearing.bearing.z as usize;
    let (nx, ni) = raceway::model_exchange_capacity(z);
    format!(
        "<h2>Model Exchange</h2>\n<p>The same binary and model description serve \
         <code>fmuType = fmi2ModelExchange</code> (<code>modelIdentifier</code> \
         <code>BallBearing</code> in both elements): the importer integrates the bearing's \
         states with its own solver, together with the rest of its model.</p>\n<ul>\n\
         <li>Supported: coupling mode force (<code>coupling = 0</code>) at the quasi-static, \
         lumped, reduced and full levels (<code>fidelity</code> 1&ndash;4), and coupling mode \
         motion (<code>coupling = 1</code>) at the lumped, reduced and full levels. Refused at \
         fmi2ExitInitializationMode with the reason logged: the kinematic level (its pedestal \
         signal is impulse responses registered spall pass by spall pass, no continuous \
         dynamics to integrate), motion coupling at the quasi-static level (an algebraic solve \
         per journal position), coupling mode tlm (a co-simulation device), and a \
         scene with more states or indicators than declared below (a second raceway spall, a \
         spall on a ball or ball waviness at the reduced and full levels: run it in \
         Co-Simulation). fmi2GetDirectionalDerivative is not provided in Model Exchange.</li>\n\
         <li>States: {nx}, the most any level has on this bearing ({z} balls: the full level's \
         9 per ball + 16), as <code>state[1]</code> &hellip; <code>state[{nx}]</code> (vr 2000 + \
         i) and <code>der(state[i])</code> (vr 3000 + i). A level with fewer states uses the \
         first ones (lumped 12, reduced 7 per ball + 12, quasi-static 2) and pads: a padding \
         state stays 0 with derivative 0 and nominal 1; what the importer writes there is \
         ignored. Nominals: displacements 1e-5 m, velocities 1e-2 m/s, angles 1 rad.</li>\n\
         <li>Event indicators: {ni} (5 per ball), the level's event functions (contacts; with a \
         spall its edges, centre and blend at the reduced and full levels), padded with the \
         constant 1. The discrete mode is frozen between events; fmi2NewDiscreteStates fires \
         the indicators that changed sign since the last completed step or event, judged at \
         the event state and 1 ns ahead of it, and re-derives the mode. Known-time \
         discontinuities (the lumped level's spall edges, jitter revolutions, pulse kinks) are \
         time events (nextEventTime). fmi2CompletedIntegratorStep asks for an event when an \
         indicator changed sign over the step.</li>\n\
         <li>Inputs: <code>shaft.speed</code> and <code>load.F*</code> may be set in \
         continuous-time mode and act on the derivatives at once; a speed change, or a change \
         that makes the level re-solve its quasi-static operating point (more than 2 %), asks \
         for an event at the next completed integrator step. Parameters only before \
         fmi2ExitInitializationMode.</li>\n\
         <li>The default scene integrated by CVODE (relative tolerance 1e-8) reproduces the \
         Co-Simulation's envelope-spectrum peak and RMS of <code>pedestal.a.z</code> within \
         0.01 %.</li>\n</ul>\n"
    )
}

/// The coupling-mode section: where the cut is, the three modes, stability, derivatives.
const COUPLING_HTML: &str = r##"<h2>Coupling modes (parameter <code>coupling</code>)</h2>
<p>The FMU is cut from the rest of the machine at the journal: the shaft (rotor model, outside) carries the inner ring's centre, the bearing (this FMU) holds the balls, the outer ring and the pedestal.</p>
<svg xmlns="http://www.w3.org/2000/svg" width="760" height="210" viewBox="0 0 760 210" font-family="sans-serif" font-size="13">
<rect x="10" y="40" width="150" height="110" fill="#e8f0ff" stroke="#345"/>
<text x="85" y="30" text-anchor="middle">master / rotor FMU</text>
<text x="85" y="90" text-anchor="middle">rotor, shaft</text>
<text x="85" y="108" text-anchor="middle">(mass M, unbalance, ...)</text>
<line x1="230" y1="20" x2="230" y2="190" stroke="#c00" stroke-width="3" stroke-dasharray="8,5"/>
<text x="230" y="205" text-anchor="middle" fill="#c00">the cut: journal = inner-ring centre</text>
<rect x="250" y="40" width="490" height="110" fill="#f6f6f6" stroke="#345"/>
<text x="495" y="30" text-anchor="middle">BallBearing FMU</text>
<rect x="265" y="60" width="110" height="70" fill="#fff" stroke="#345"/>
<text x="320" y="90" text-anchor="middle">inner ring</text>
<text x="320" y="108" text-anchor="middle">(journal)</text>
<circle cx="420" cy="80" r="12" fill="#ddd" stroke="#345"/><circle cx="420" cy="112" r="12" fill="#ddd" stroke="#345"/>
<text x="420" y="145" text-anchor="middle">balls</text>
<rect x="465" y="60" width="120" height="70" fill="#fff" stroke="#345"/>
<text x="525" y="90" text-anchor="middle">outer ring +</text>
<text x="525" y="108" text-anchor="middle">pedestal</text>
<line x1="585" y1="95" x2="640" y2="95" stroke="#345"/><polyline points="640,95 648,85 656,105 664,85 672,105 680,95 720,95" fill="none" stroke="#345"/>
<text x="680" y="125" text-anchor="middle">k_p, c_p to ground</text>
<line x1="160" y1="75" x2="265" y2="75" stroke="#06c" stroke-width="2" marker-end="url(#a)"/>
<text x="197" y="68" text-anchor="middle" fill="#06c">journal.x/y/z, journal.v.*</text>
<line x1="265" y1="118" x2="160" y2="118" stroke="#090" stroke-width="2" marker-end="url(#b)"/>
<text x="197" y="137" text-anchor="middle" fill="#090">bearing.F.x/y/z</text>
<defs><marker id="a" markerWidth="8" markerHeight="8" refX="8" refY="4" orient="auto"><path d="M0,0 L8,4 L0,8 z" fill="#06c"/></marker><marker id="b" markerWidth="8" markerHeight="8" refX="8" refY="4" orient="auto"><path d="M0,0 L8,4 L0,8 z" fill="#090"/></marker></defs>
</svg>
<table>
<tr><th>coupling</th><th>inputs</th><th>what the FMU does</th><th>outputs</th></tr>
<tr><td>0 force (default)</td><td><code>shaft.speed</code>, <code>load.Fx/Fy/Fz</code> (the external force on the inner ring); <code>journal.*</code> ignored</td><td>integrates the inner ring (with its mass <code>inner_ring.mass</code>) under the loads and the contact forces: one-way studies, loads from a gearbox or a measured spectrum</td><td>everything, <code>ring.x/y/z</code> the computed ring motion, <code>bearing.F.*</code> the contact force sum on the ring</td></tr>
<tr><td>1 motion</td><td><code>shaft.speed</code>, <code>journal.x/y/z</code> [m], <code>journal.v.x/y/z</code> [m/s]; <code>load.F*</code> only at initialization</td><td>prescribes the inner ring's translation: within a communication step [t_k, t_k+1] the ring moves as x(t) = x_k + v_k (t − t_k) with the values set at t_k; the balls, the outer ring and the pedestal respond. Two-way coupling to a rotor model that owns the shaft mass.</td><td><code>bearing.F.x/y/z</code> = the reaction of the bearing on the journal (sum of the contact forces on the inner ring); <code>ring.x/y/z</code> = the journal displacement; pedestal accelerations and contact forces as in force mode</td></tr>
<tr><td>2 tlm</td><td><code>shaft.speed</code>, <code>load.F*</code>, <code>tlm.c0.y/z</code>, <code>tlm.c1.y/z</code> [N], <code>tlm.Zc</code> [N s/m]; <code>journal.*</code> ignored</td><td>force mode plus a transmission line through the shaft, computed by the JeffcottRotor (<code>coupling = 1</code>, <code>tlm.delay</code> = the communication step): the inner ring, which holds the journal's mass, feels the loads and the line's force c0 + (c1 − c0)(t − t_k)/H − Zc v over each step. The line is passive: the pair is stable at every communication step with plain value exchange (libcosim, fmpy), and no output depends on an input at the same instant, so the master's order of sets and gets does not matter. Lumped, reduced and full levels.</td><td>as in force mode; <code>ring.v.y/z</code> go to the rotor's <code>tlm.v.y/z</code></td></tr>
</table>
<p><b>Frame and origin.</b> <code>journal.*</code> and <code>ring.*</code> share the inertial frame (x along the shaft axis and the axial load, z up: the radial load of the default scene acts along −z) and the origin: the inner-ring centre of the unloaded, centred bearing with the pedestal at rest on unloaded supports. In motion mode the inner ring has no mass of its own in the FMU: put the shaft's mass and these masses in the rotor model (the journal mass): at the lumped level (2), <code>inner_ring.mass</code> plus half the balls' mass (z m_b/2 = 0.0589 kg for the default bearing: the lumped level carries half of the balls' inertia on the ring and half on the pedestal; in force mode it integrates the ring with m1 = <code>inner_ring.mass</code> + z m_b/2); at the reduced (3) and full (4) levels, <code>inner_ring.mass</code> only (the balls are bodies of the FMU). A force-mode run equivalent to a rotor of journal mass M in motion mode therefore sets <code>inner_ring.mass</code> = M − z m_b/2 at level 2 and M at levels 3 and 4.</p>
<p><b>Initialization.</b> In motion mode the loads <code>load.F*</code> define the quasi-static (L1) start: the FMU places the ring at the static equilibrium under these loads, and <code>ring.x/y/z</code> read in initialization mode (or after fmi2ExitInitializationMode) are that equilibrium. If the master has not set any <code>journal.*</code> before fmi2ExitInitializationMode, the journal starts there at rest (<code>journal.*</code> then read back as that equilibrium); start the rotor there (displacement = <code>ring.*</code>, the rotor's static load equal to <code>load.F*</code>) to begin without a transient. Later changes of <code>load.F*</code> are ignored in motion mode (the rotor carries the loads); when <code>shaft.speed</code> has moved by more than 2 % since the last update, the lumped level updates its cage speed (L1 and the balls' steady rotation under the traction) at the start of the next fmi2DoStep, at the load the ring carries then (minus <code>bearing.F</code> from the state after all inputs of the communication point are set, so the order in which the master sets <code>shaft.speed</code> and <code>journal.*</code> does not matter); between updates the cage speed is the last ratio times the speed.</p>
<p><b>Levels.</b> Lumped (2), reduced (3) and full (4) prescribe the inner-ring translation in their equations of motion (reduced: its reaction Jacobian is the central difference of its reaction, traction included); at the full level the ring's tilt is held at zero (decision D1; the interface has no rotations). Kinematic (0) and quasi-static (1) give the reaction from the displacement-controlled quasi-static equilibrium of every ball (centrifugal and gyroscopic forces included) with the pedestal in series on its springs; no velocity dependence.</p>
<h3>Co-simulation stability</h3>
<p>For masters that exchange values only, couple through the transmission line (<code>coupling = 2</code>): it is stable at every step. With the cut at the contact (motion mode) the FMU logs at initialization the largest stable step of value exchange, 2c/k per axis from the reaction's stiffness k and damping c at the start (about 0.6 µs on the default bearing), and the first longer communication step returns fmi2Warning.</p>
<p>A bearing is stiff (k_b ≈ 1e8 N/m). For a rotor of mass M on it, ω = √(k_b/M), with damping ratio ζ (rotor damping plus contact damping, both enter alike to first order in ωH), an explicit coupling that holds the force constant over the macro step H is stable only for <b>ωH &lt; 4ζ</b>, and always unstable without damping; for M = 2 kg and ζ = 0.02 that is H &lt; 10 µs. Linear extrapolation of the inputs extends it to ωH &lt; 0.40/0.50/0.69/0.90 for ζ = 0.01/0.02/0.05/0.1. Typical 0.1–1 ms master steps are therefore unstable with a plain cut at the bearing. Remedies: small macro steps (cheap here: the internal steps are 2–5 µs anyway), cutting at a softer interface, input extrapolation, iterated coupling with state rollback (fmi2GetFMUstate/fmi2SetFMUstate), or the interface Jacobian below, which makes the coupling stable for any step on a linear bearing. Measured (test T7, <code>tests/stability_cosim.rs</code>: this bearing at zero speed under Fa = 4000 N, Fr = 1000 N, a 2 kg rotor with 2 % damping, k = −∂F_z/∂z = 3.24e8 N/m from the directional derivatives, ω = 12 724 rad/s, ζ = 0.022 including the contact damping): constant-force boundary H = 6.90 µs against 4ζ/ω = 6.90 µs; with the interface Jacobian the coupled run decays at H = 138 µs and at H = 1 ms (ωH ≈ 13).</p>
<h3>Interface Jacobian (fmi2GetDirectionalDerivative)</h3>
<p>In motion mode the FMU provides ∂<code>bearing.F.*</code>/∂<code>journal.*</code> (a 3×6 block: contact stiffness ∂F/∂x and contact damping ∂F/∂v) at the current communication point, for the state and journal just set (direct feedthrough). At the lumped level it is analytic per closed contact: stiffness 1.5 K δ^½ along the normal, the geometric term Q/|a| (P − n nᵀ) of the normal turning with the displacement, the contact damping c_br along the normal and its dependence on the displacement, with the spall's modified Hertz constant for a ball in it. At the full level without traction (<code>[full] traction = false</code> in a scene) it is analytic in the same way (the normal also turns with the ring's azimuthal displacement; the ring's tilt is held); a contact that the spall alters is differentiated numerically. With traction (the default) it is the central difference of the full reaction, traction included: the slip-dependent traction adds a large velocity dependence (about 1000–1600 N s/m on the diagonal of ∂F/∂v for the default bearing and scene, against about 93 N s/m from the contact damping c_br) and about 1 % to ∂F/∂x. At kinematic and quasi-static levels it is the quasi-static stiffness with the pedestal in series (∂F/∂v = 0). Also provided: ∂<code>ring.*</code>/∂<code>journal.x/y/z</code> = identity and zero derivatives with respect to <code>load.F*</code>. Other pairs return fmi2Error naming them; in force mode the function returns fmi2Error.</p>
<p>Use: at t_k set <code>journal.*</code>, read F_k = <code>bearing.F.*</code> and K = ∂F/∂x, C = ∂F/∂v (seed vectors e_j on the knowns, or one call per column). Integrate the rotor over [t_k, t_k + H] with the linearized bearing force F ≈ F_k + K (x − x_k) + C (v − v_k) implicitly (linearly implicit coupling, e.g. an exact or trapezoidal step of the linear rotor+bearing system); then step both FMUs. The co-simulation is then stable far beyond ωH = 4ζ.</p>
"##;

/// The HTML page of the FMU without a scene resource. `availability` is
/// [`fidelity_availability`]'s result (fmu-build computes it).
pub fn documentation_html(
    bearing: &BearingFile,
    availability: &[(Fidelity, Result<(), String>)],
) -> String {
    documentation_html_for(&Base::default_for(bearing), availability)
}

/// The spalls section: the parameter spalls, the fixed ones, the shared mode, and what the
/// scene resource fixes.
fn spalls_html(base: &Base) -> String {
    let scene = &base.scene;
    let n = scene.n_defects();
    let resource = match &base.scene_digest {
        None => "<p>This FMU has no scene resource: its start values are the default \
                 scene's (<code>resources/default-scene.toml</code>) on its bearing, with one \
                 spall (<code>defect.*</code>) and <code>defect2.ring</code> … \
                 <code>defect4.ring</code> = 0; no waviness, no roughness.</p>\n"
            .to_string(),
        Some(d) => format!(
            "<p>This FMU was made from the scene '{}' (<code>raceway fmu --scene</code>), \
             shipped as <code>resources/{SCENE_RESOURCE}</code> (SHA-256 <code>{d}</code>, part \
             of the model description and so of the GUID: an FMU whose resource was edited \
             refuses to instantiate). Its fidelity, operating point, solver, lumped and full \
             options, mounting and coupling are the parameters' and inputs' start values; its \
             spalls 1–4 ({} in the scene) the start values of <code>defect.*</code> … \
             <code>defect4.*</code>; its spalls 5 and later ({} here), its per-spall modes, \
             waviness ({}), roughness ({}), pulse and resonator are fixed.</p>\n",
            esc(&scene.name),
            n.min(SPALL_SLOTS),
            n.saturating_sub(SPALL_SLOTS),
            if scene.waviness.is_some() {
                "present"
            } else {
                "none"
            },
            if scene.roughness.is_some() {
                "present"
            } else {
                "none"
            },
        ),
    };
    format!(
        "<h2>Spalls (parameters <code>defect.*</code>, <code>defect2.*</code> … \
         <code>defect4.*</code>)</h2>\n<p>Up to four spalls are parameters: spall 1 is \
         <code>defect.ring</code>, <code>defect.width</code>, <code>defect.depth</code>, \
         <code>defect.theta0</code>, <code>defect.ball</code>; spalls 2–4 the same fields under \
         <code>defect2</code>, <code>defect3</code>, <code>defect4</code> (value references \
         130–144); a ring of 0 leaves the spall out. The simulation's spalls are the parameter \
         spalls whose ring is not 0, in this order, then the scene resource's spalls 5 and \
         later (fixed). <code>defect.mode</code> is the one mode of every spall that has no mode \
         of its own in the scene resource. Two spalls on one race must not overlap, a spalled \
         ball must exist, and a spall on a ball needs the lumped level: otherwise \
         fmi2ExitInitializationMode returns fmi2Error with a message naming the parameters \
         (e.g. <code>defect2.*</code>). Waviness and roughness are not parameters: they come \
         from the scene resource only.</p>\n{resource}"
    )
}

/// The HTML page of the FMU made from `base`. `availability` is [`fidelity_availability`]'s
/// result (fmu-build computes it).
pub fn documentation_html_for(
    base: &Base,
    availability: &[(Fidelity, Result<(), String>)],
) -> String {
    let bearing = base.bearing();
    let t = table_for(&base.scene);
    let guid = crate::description::guid_for(base);
    let info = crate::description::model_info_for(base);
    let mut h = String::new();
    h.push_str("<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n");
    h.push_str("<title>BallBearing FMU</title>\n<style>body{font-family:sans-serif;max-width:70em;margin:2em auto;line-height:1.4}table{border-collapse:collapse}td,th{border:1px solid #aaa;padding:2px 6px;text-align:left;vertical-align:top}code{background:#f3f3f3}</style>\n</head>\n<body>\n");
    h.push_str(
        "<h1>BallBearing: high-speed angular-contact ball bearing with raceway and ball spalls</h1>\n",
    );
    h.push_str(&format!(
        "<p>{}. FMI 2.0 Co-Simulation and Model Exchange FMU generated by {} (GUID <code>{}</code>).</p>\n",
        esc(&info.description),
        esc(&info.generation_tool),
        esc(&guid)
    ));
    h.push_str("<p>The FMU simulates the vibration of a ball bearing with localized spalls (up to four as parameters, more from a scene resource) on its races and balls after Niu, Cao, He and Li (ASME J. Manuf. Sci. Eng. 136 (2014) 041015): given the shaft speed and the external load on the inner ring (inputs; or, in coupling mode motion, the journal's displacement and velocity), it integrates the bearing dynamics with an adaptive explicit Runge–Kutta method to exactly each communication point and returns pedestal accelerations, displacements, contact forces, the bearing reaction on the shaft, the cage speed, and per ball the orbital speed and a flag that is 1 while the ball touches neither race (outputs).</p>\n");
    h.push_str(&format!(
        "<h2>Bearing</h2>\n<p>'{}' with {} balls, ball diameter {} m, pitch diameter {} m, free contact angle {}°. The bearing is read at instantiation from <code>resources/bearing.toml</code>; the number of per-ball outputs follows the ball count, so a different bearing needs a different FMU (<code>raceway fmu --bearing &lt;preset|file.toml&gt;</code>, or <code>raceway fmu --scene &lt;scene.toml&gt;</code> for a scene's bearing with the scene as the FMU's base).</p>\n",
        esc(&bearing.name),
        bearing.bearing.z,
        bearing.bearing.ball_diameter,
        bearing.bearing.pitch_diameter,
        bearing.bearing.contact_angle_free_deg
    ));

    h.push_str(&spalls_html(base));

    h.push_str("<h2>Fidelity levels (parameter <code>fidelity</code>)</h2>\n<table>\n<tr><th>code</th><th>level</th><th>what it computes</th><th>in this build</th></tr>\n");
    for (f, avail) in availability {
        let a = match avail {
            Ok(()) => match level(*f).deprecated {
                Some(why) => format!("available, deprecated (to be removed: {})", esc(why)),
                None => "available".to_string(),
            },
            Err(m) => format!("not available: {}", esc(m)),
        };
        h.push_str(&format!(
            "<tr><td>{}</td><td>{}</td><td>{}</td><td>{}</td></tr>\n",
            f.code(),
            f.name(),
            esc(level(*f).summary),
            a
        ));
    }
    h.push_str("</table>\n<p>A level that is not available makes <code>fmi2ExitInitializationMode</code> return fmi2Error with the library's message.</p>\n");

    let enums = enumerations();
    h.push_str("<h2>Variables</h2>\n<p>Inputs are held constant over a communication step. Parameters are fixed: they can be set after fmi2Instantiate and in initialization mode only (fmi2Reset to change them later). Value references are stable. The mode switches are Enumerations: an importer shows their items by name; the values (listed in the range column) are read and written with fmi2GetInteger and fmi2SetInteger, and a value that is no item is refused.</p>\n<table>\n<tr><th>name</th><th>vr</th><th>causality</th><th>type</th><th>unit (display)</th><th>start</th><th>range</th><th>meaning</th></tr>\n");
    for e in &t {
        let v = &e.var;
        let unit = match (&v.unit, &v.display_unit) {
            (Some(u), Some(d)) => format!("{u} ({d})"),
            (Some(u), None) => u.clone(),
            _ => "-".into(),
        };
        let items = v
            .declared_type
            .as_ref()
            .and_then(|t| enums.iter().find(|e| &e.name == t));
        let start = match &v.start {
            Start::Real(x) => format!("{x}"),
            Start::Integer(x) => match items.and_then(|e| e.item(*x)) {
                Some(item) => format!("{x} ({})", esc(&item.name)),
                None => format!("{x}"),
            },
            Start::Boolean(x) => format!("{x}"),
            Start::String(x) => esc(x),
            Start::None => "calculated".into(),
        };
        let range = match (items, v.min, v.max) {
            (Some(e), _, _) => e
                .items
                .iter()
                .map(|i| format!("{} {}", i.value, esc(&i.name)))
                .collect::<Vec<_>>()
                .join(", "),
            (None, None, None) => String::new(),
            (None, lo, hi) => format!(
                "[{}, {}]",
                lo.map_or("-∞".into(), |x| x.to_string()),
                hi.map_or("+∞".into(), |x| x.to_string())
            ),
        };
        let kind = match e.role {
            Access::Input { .. } | Access::Journal(_) | Access::Line(_) => "input",
            Access::Param { .. } => "parameter (fixed)",
            Access::Output(_) | Access::Stat(_) | Access::RingVelocity(_) => "output",
            Access::State(_) | Access::Derivative(_) => "local (Model Exchange)",
        };
        h.push_str(&format!(
            "<tr><td><code>{}</code></td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td></tr>\n",
            esc(&v.name),
            v.vr,
            kind,
            match (v.ty, &v.declared_type) {
                (VarType::Enumeration, Some(t)) => format!("Enumeration <code>{}</code>", esc(t)),
                (ty, _) => ty.name().to_string(),
            },
            esc(&unit),
            start,
            range,
            esc(&v.description)
        ));
    }
    h.push_str("</table>\n");

    h.push_str(COUPLING_HTML);
    h.push_str(&model_exchange_html(bearing));

    h.push_str("<h2>Solver</h2>\n<ul>\n<li><code>solver.method</code> (Enumeration <code>IntegrationMethod</code>): 0 <code>rkf45</code> (RKF45), 1 <code>dopri5</code> (DOPRI5), 2 <code>dop853</code> (DOP853, default), explicit embedded Runge–Kutta pairs with step-size control; every communication step ends exactly at t + h, and a change of the inputs is a restart of the integrator.</li>\n<li><code>solver.rtol</code>: relative tolerance (absolute tolerances are rtol × each state's nominal value). The <code>tolerance</code> of fmi2SetupExperiment, when defined, overrides it; the DefaultExperiment's tolerance is 1e-6. Tolerances below 1e-14 are refused (fmi2Error): round-off would make the integrator crawl instead of fail.</li>\n<li><code>solver.pi_beta</code>: β of the PI step-size controller in [0, 0.2]; 0 (default) is the I-controller, the more accurate at equal work at rtol 1e-6 and tighter. With the cage (on by default) the full level's waveform branches at grazing contacts whatever the controller or tolerance: runs that differ by round-off part after tens of milliseconds, so compare them by spectra and statistics over long windows (README, section on tolerances, and docs/research/cage.md in the raceway repository).</li>\n<li><code>solver.max_steps</code>: work budget per communication step: attempted integrator steps (spall stops and contact events included) and, at the kinematic level, the spall passes registered (one unit each), so that no call runs unbounded whatever the inputs. When it is exhausted, or the step size underflows, or the state becomes non-finite, fmi2DoStep returns fmi2Discard and logs why (always, whatever the logging settings): the cause and its numbers, where the integrator stopped, and the work the step discarded. The FMU then stays at the step's start, the last successful communication point: every output reads that point, never the failed attempt; fmi2GetRealStatus(fmi2LastSuccessfulTime) is its time, fmi2GetBooleanStatus(fmi2Terminated) is true, and fmi2GetFMUstate gives that state. After fmi2Error from fmi2DoStep the outputs are likewise those of the step's start.</li>\n<li>Integer outputs <code>solver.steps</code>, <code>solver.rejected</code>, <code>solver.rhs_evals</code> count the integrator's work from the start to the current communication point (the work of a discarded step is in its message, not in them).</li>\n</ul>\n");

    h.push_str("<h2>Behaviour of the FMU</h2>\n<ul>\n<li>Any number of instances per process, on any threads; no global state. The FMU state can be saved (fmi2GetFMUstate) and serialized; the serialized form is versioned, pointer-free, carries the GUID, and restores bit-identically in another process.</li>\n<li>Non-finite inputs or parameters, values outside the declared ranges and impossible geometry are rejected with fmi2Error and a message naming the variable; an fmi2Set* call with a rejected value applies none of its values. No output is ever returned as NaN with fmi2OK.</li>\n<li>A wrong call sequence returns fmi2Error (\"illegal call sequence\") and has no effect. fmi2Reset returns to the just-instantiated state from any state but Fatal.</li>\n<li>Log categories: logEvents, logSolver, logStatusWarning, logStatusDiscard, logStatusError, logStatusFatal, logAll. Discard, Error and Fatal messages are always passed to the logger.</li>\n<li>fmi2GetDirectionalDerivative is provided in coupling mode motion (see above); fmi2SetRealInputDerivatives, fmi2GetRealOutputDerivatives and fmi2CancelStep return fmi2Error (not supported). All 44 FMI 2.0 functions are exported; a function of the other interface returns fmi2Error with no effect.</li>\n</ul>\n");

    h.push_str("<h2>Limits of validity</h2>\n<ul>\n<li>Rigid rings and balls apart from the Hertz contacts; the pedestal (with the outer ring) is a 2-DOF mass–spring–damper; the spall is a band across the whole groove with a smooth floor and sharp edges.</li>\n<li>Shaft speed ≥ 0 (rotation about +x); the loads must keep the balls loaded enough for the model's kinematic assumptions (an axial preload, as in the default scene, is advisable).</li>\n<li>Up to four spalls are parameters (<code>defect.*</code> … <code>defect4.*</code>); more, and waviness and roughness, come fixed from a scene resource (<code>raceway fmu --scene</code>). Each spall's width must be smaller than the ball diameter; depth and width below 0.1 m; spalls on one race must not overlap.</li>\n<li>Outputs in the first ≈20 ms contain the start-up transient from the quasi-static initial state.</li>\n<li>Results agree between communication step sizes within the integrator tolerance (inputs are piecewise constant).</li>\n</ul>\n");

    h.push_str("<h2>Files</h2>\n<ul>\n<li><code>resources/bearing.toml</code>: the bearing of this FMU; <code>resources/scene.toml</code> (an FMU made with <code>--scene</code> only): its base scene; <code>resources/presets/</code>: the bearing presets; <code>resources/default-scene.toml</code>: the default scene.</li>\n<li><code>documentation/BallBearing_in.csv</code>, <code>BallBearing_ref.csv</code>, <code>BallBearing_ref.opt</code>: a reference run in cross-check style (inputs, outputs, and StartTime/StopTime/StepSize/RelTol).</li>\n</ul>\n");

    h.push_str("<h2>How to cite</h2>\n<p>Linkai Niu, Hongrui Cao, Zhengjia He, Yamin Li: <i>Dynamic Modeling and Vibration Response Simulation for High Speed Rolling Ball Bearings With Localized Surface Defects in Raceways</i>, ASME Journal of Manufacturing Science and Engineering 136(4), 041015 (2014), doi:10.1115/1.4027334; and the raceway software (version ");
    h.push_str(&esc(&info.version));
    h.push_str(").</p>\n</body>\n</html>\n");
    h
}
