//! The bounded fuzz run CI does: a few thousand cases of each target in this process, with no
//! panic allowed and every case well under the hang limit; plus the worker binary on a short
//! run, so the process machinery (restarts, findings, summary) is exercised too.

use solari_fuzz::run::{Harness, Progress, Target, run_range};
use solari_fuzz::targets::Outcome;
use std::collections::BTreeMap;
use std::time::Instant;

fn bounded(target: Target, cases: u64) {
    let seeds = solari_fuzz::seeds::load(&solari_fuzz::seeds::default_dirs());
    let work = std::env::temp_dir().join(format!("solari-fuzz-{target:?}-{}", std::process::id()));
    let h = Harness::new(7, vec![target], seeds, &work);
    let mut reasons: BTreeMap<String, u64> = BTreeMap::new();
    let tally = run_range(
        &h,
        0..cases,
        &Progress::default(),
        Instant::now(),
        |_, _, o, _| {
            if let Outcome::Refused(r) = o {
                // The reason without the file name and numbers: "mesh 0 primitive 0: ..." etc.
                let key: String = r
                    .split(": ")
                    .skip(1)
                    .collect::<Vec<_>>()
                    .join(": ")
                    .chars()
                    .filter(|c| !c.is_ascii_digit())
                    .take(60)
                    .collect();
                *reasons.entry(key).or_default() += 1;
            }
        },
    );
    let _ = std::fs::remove_dir_all(&work);
    let mut top: Vec<_> = reasons.into_iter().collect();
    top.sort_by_key(|(_, n)| std::cmp::Reverse(*n));
    eprintln!(
        "{target:?}: {} cases, {} accepted, {} refused, slowest case {} at {:.3} s; top refusals:",
        tally.cases, tally.ok, tally.refused, tally.slowest.0, tally.slowest.1
    );
    for (r, n) in top.iter().take(12) {
        eprintln!("  {n:>6}  {r}");
    }
    assert!(tally.panics.is_empty(), "panics: {:?}", tally.panics);
    assert!(
        tally.slowest.1 < 5.0,
        "case {} took {:.1} s",
        tally.slowest.0,
        tally.slowest.1
    );
    assert!(
        tally.ok > 0,
        "nothing was accepted: the mutations never reach past parsing"
    );
}

#[test]
fn importer_survives_a_bounded_run() {
    bounded(Target::Import, 3000);
}

#[test]
fn command_line_survives_a_bounded_run() {
    bounded(Target::Cli, 2000);
}

#[test]
fn the_worker_binary_runs_and_reports_clean() {
    let out = std::env::temp_dir().join(format!("solari-fuzz-bin-{}", std::process::id()));
    let status = std::process::Command::new(env!("CARGO_BIN_EXE_solari-fuzz"))
        .args([
            "--cases", "600", "--jobs", "2", "--chunk", "200", "--seed", "3",
        ])
        .arg("--out")
        .arg(&out)
        .output()
        .expect("run solari-fuzz");
    let summary: serde_json::Value =
        serde_json::from_slice(&std::fs::read(out.join("summary.json")).expect("summary"))
            .expect("json");
    let _ = std::fs::remove_dir_all(&out);
    assert!(
        status.status.success(),
        "{}",
        String::from_utf8_lossy(&status.stderr)
    );
    assert_eq!(summary["cases"], 600);
    assert_eq!(summary["clean"], true);
}
