//! `raceway levels`: the fidelity levels this build knows, from the library's registry
//! (`raceway::models::LEVELS`), so that users and scripts need not hard-code them.

use raceway::models::LEVELS;
use serde::Serialize;
use std::fmt::Write as _;

/// Arguments of `raceway levels`.
#[derive(clap::Args)]
pub struct Args {
    /// Print JSON (an array in ladder order; keys name, code, label, summary, distributed,
    /// ball_spalls, deprecated: the reason, or null) instead of a table
    #[arg(long)]
    pub json: bool,
}

/// One level as `--json` prints it.
#[derive(Serialize)]
struct Row {
    name: &'static str,
    code: i32,
    label: &'static str,
    summary: &'static str,
    distributed: bool,
    ball_spalls: bool,
    deprecated: Option<&'static str>,
}

/// Runs the subcommand.
pub fn run(args: Args) -> Result<(), String> {
    let rows: Vec<Row> = LEVELS
        .iter()
        .map(|l| Row {
            name: l.name,
            code: l.code,
            label: l.label,
            summary: l.summary,
            distributed: l.distributed,
            ball_spalls: l.ball_spalls,
            deprecated: l.deprecated,
        })
        .collect();
    let mut out = String::new();
    if args.json {
        let text = serde_json::to_string_pretty(&rows).map_err(|e| e.to_string())?;
        let _ = writeln!(out, "{text}");
    } else {
        let _ = writeln!(
            out,
            "Fidelity levels (scene `fidelity`, CLI `--fidelity`, FMU parameter `fidelity` = code):"
        );
        for r in &rows {
            let _ = writeln!(out);
            let tag = if r.deprecated.is_some() {
                "  [deprecated]"
            } else {
                ""
            };
            let _ = writeln!(out, "  {} (code {}, {}){tag}", r.name, r.code, r.label);
            let _ = writeln!(out, "    {}", r.summary);
            let yes = |b: bool| if b { "yes" } else { "no" };
            let _ = writeln!(
                out,
                "    waviness and roughness: {}; spalls on balls: {}",
                yes(r.distributed),
                yes(r.ball_spalls)
            );
            if let Some(why) = r.deprecated {
                let _ = writeln!(out, "    deprecated: {why}");
            }
        }
    }
    use std::io::Write;
    // A closed pipe (e.g. `| head`) is not an error.
    let _ = std::io::stdout().lock().write_all(out.as_bytes());
    Ok(())
}
