//! `dembound benchmarks` (issue 30): an unknown name is bad input (exit 2,
//! the names listed, nothing written); a run writes the whole set (report
//! in Markdown and self-contained HTML, summary CSV, one figure per plot)
//! and nothing else; a run stopped by SIGTERM leaves nothing.

mod common;

use common::dembound;
use std::path::Path;

/// The files in `dir`, sorted (the output record included).
fn files(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(dir)
        .map(|r| {
            r.flatten()
                .map(|e| e.file_name().to_string_lossy().into_owned())
                .collect()
        })
        .unwrap_or_default();
    v.sort();
    v
}

#[test]
fn an_unknown_name_exits_2_listing_the_names_and_writes_nothing() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("b");
    let o = dembound()
        .args([
            "benchmarks",
            "chung-ooi-1",
            "granular-nope",
            "--quick",
            "--out",
        ])
        .arg(&out)
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(2));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("unknown benchmark `granular-nope`"), "{err}");
    for n in ["chung-ooi-1", "chung-ooi-4", "chung-ooi-8"] {
        assert!(err.contains(n), "{err}");
    }
    assert!(!out.exists(), "nothing is created for bad input");
}

/// `--seeds` outside 1–16, or for a benchmark that pours no random heap,
/// is bad input: exit 2, the option, its value and what is allowed named,
/// nothing written (refused before any run).
#[test]
fn seeds_out_of_range_or_for_another_benchmark_exit_2_and_write_nothing() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("b");
    for (args, allowed) in [
        (vec!["repose", "--seeds", "0"], "1 to 16"),
        (vec!["repose", "--seeds", "17"], "1 to 16"),
        (vec!["chung-ooi-1", "--seeds", "2"], "only to repose"),
        (vec!["--seeds", "2"], "only to repose"),
    ] {
        let o = dembound()
            .arg("benchmarks")
            .args(&args)
            .args(["--quick", "--out"])
            .arg(&out)
            .output()
            .unwrap();
        assert_eq!(o.status.code(), Some(2), "{args:?}");
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(
            err.contains(&format!("--seeds {}", args[args.len() - 1])) && err.contains(allowed),
            "{args:?}: {err}"
        );
        assert!(!out.exists(), "{args:?}: nothing is created for bad input");
    }
}

#[test]
fn without_out_it_is_bad_input_and_list_needs_none() {
    let o = dembound().args(["benchmarks", "--quick"]).output().unwrap();
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("--out"));
    let o = dembound().args(["benchmarks", "--list"]).output().unwrap();
    assert!(o.status.success());
    let text = String::from_utf8_lossy(&o.stdout);
    assert!(
        text.lines().count() >= 8 && text.contains("chung-ooi-5"),
        "{text}"
    );
}

#[test]
fn a_quick_run_writes_the_whole_set() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("b");
    let o = dembound()
        .args([
            "benchmarks",
            "chung-ooi-1",
            "chung-ooi-4",
            "--quick",
            "-q",
            "--out",
        ])
        .arg(&out)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let names = files(&out);
    for f in [
        "report.md",
        "report.html",
        "summary.csv",
        "chung-ooi-1.png",
        "chung-ooi-1.svg",
        "chung-ooi-4-et.png",
        "chung-ooi-4-spin.png",
        "chung-ooi-4-angle.png",
    ] {
        assert!(names.iter().any(|n| n == f), "{f} missing: {names:?}");
    }
    // Nothing else but the output record: no staging left behind.
    let others: Vec<&String> = names
        .iter()
        .filter(|n| {
            !(n.ends_with(".png")
                || n.ends_with(".svg")
                || n.starts_with("report.")
                || *n == "summary.csv"
                || *n == ".dembound.json")
        })
        .collect();
    assert!(others.is_empty(), "{others:?}");
    let md = std::fs::read_to_string(out.join("report.md")).unwrap();
    assert!(
        md.contains("## Summary") && md.contains("## chung-ooi-1") && md.contains("## chung-ooi-4")
    );
    assert!(md.contains("![") && md.contains("chung-ooi-4-et.png"));
    assert!(
        !md.contains("## chung-ooi-2"),
        "only the named benchmarks run"
    );
    let html = std::fs::read_to_string(out.join("report.html")).unwrap();
    assert!(html.contains("data:image/png;base64,") && !html.contains("src=\"chung-ooi"));
    let csv = std::fs::read_to_string(out.join("summary.csv")).unwrap();
    assert!(csv.lines().count() > 5 && csv.contains("pass"), "{csv}");
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert!(stdout.contains("of 2 benchmarks passed"), "{stdout}");
}

#[cfg(unix)]
#[test]
fn a_run_stopped_by_sigterm_leaves_nothing() {
    use std::process::{Command, Stdio};
    use std::time::Duration;
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("b");
    // The full suite takes seconds: stopped while computing.
    let mut child = Command::new(env!("CARGO_BIN_EXE_dembound"))
        .args(["benchmarks", "-q", "--out"])
        .arg(&out)
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    std::thread::sleep(Duration::from_millis(300));
    let _ = Command::new("kill")
        .arg("-TERM")
        .arg(child.id().to_string())
        .status();
    let status = child.wait().unwrap();
    assert!(!status.success());
    let left = files(&out);
    assert!(
        left.iter()
            .all(|n| !n.starts_with("report") && !n.starts_with(".dembound-staging")),
        "{left:?}"
    );
}
