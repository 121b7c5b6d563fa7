//! Output is all or nothing (issue 10): a command stopped by SIGINT or
//! SIGTERM, a failure while publishing, or several commands writing into
//! one directory at once leave either a complete set or the previous
//! state, and no staging files; a bad `--out` is refused before computing.
#![cfg(unix)]

mod common;

use common::dembound;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

const RECORD: &str = ".dembound.json";
const G: f64 = 9.81;

fn spawn(args: &[&str], out: &Path) -> Child {
    Command::new(env!("CARGO_BIN_EXE_dembound"))
        .args(args)
        .arg("--out")
        .arg(out)
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .expect("the binary starts")
}

fn send(child: &Child, signal: &str) {
    let status = Command::new("kill")
        .arg(format!("-{signal}"))
        .arg(child.id().to_string())
        .status()
        .expect("kill runs");
    // The process may have ended already (then kill fails): fine.
    let _ = status;
}

/// Every path under `root` (files and folders), relative, sorted.
fn tree(root: &Path) -> Vec<String> {
    fn walk(root: &Path, dir: &Path, out: &mut Vec<String>) {
        let Ok(entries) = std::fs::read_dir(dir) else {
            return;
        };
        for e in entries.flatten() {
            let path = e.path();
            out.push(
                path.strip_prefix(root)
                    .unwrap()
                    .to_string_lossy()
                    .into_owned(),
            );
            if path.is_dir() {
                walk(root, &path, out);
            }
        }
    }
    let mut out = Vec::new();
    walk(root, root, &mut out);
    out.sort();
    out
}

/// Names that only a write in progress may leave: staging folders, the
/// previous files of a commit, temporary files.
fn leftovers(root: &Path) -> Vec<String> {
    tree(root)
        .into_iter()
        .filter(|p| {
            let name = p.rsplit('/').next().unwrap_or(p);
            name.starts_with(".dembound-") || name.ends_with(".tmp") || name.ends_with(".removing")
        })
        .collect()
}

/// The staging folder inside `dir` holding `file`, if there is one yet.
fn staging_holds(dir: &Path, file: &str) -> bool {
    std::fs::read_dir(dir).is_ok_and(|entries| {
        entries.flatten().any(|e| {
            e.file_name()
                .to_string_lossy()
                .starts_with(".dembound-staging-")
                && e.path().join(file).exists()
        })
    })
}

/// Polls until `ready` or the child has ended (or a minute passed).
fn wait_until(child: &mut Child, ready: impl Fn() -> bool) {
    let start = Instant::now();
    while !ready() && start.elapsed() < Duration::from_secs(60) {
        if child.try_wait().expect("wait").is_some() {
            return;
        }
        std::thread::sleep(Duration::from_millis(1));
    }
}

/// 0 if the process finished before `signal` reached it, else 128 + the
/// signal's number: the exit code of the handler (130, 143), or the
/// default action's death when the signal came before the handler was
/// installed (the first milliseconds, before any output exists). Any
/// other ending fails the test.
fn stopped(child: Child, signal: &str) -> i32 {
    use std::os::unix::process::ExitStatusExt;
    let out = child.wait_with_output().expect("wait");
    let number = match signal {
        "INT" => 2,
        "TERM" => 15,
        _ => unreachable!(),
    };
    let code = match (out.status.code(), out.status.signal()) {
        (Some(code), _) => code,
        (None, Some(s)) if s == number => 128 + s,
        _ => panic!("ended otherwise: {:?}", out.status),
    };
    assert!(
        code == 128 + number || code == 0,
        "SIG{signal}: exit {code}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    code
}

/// Checks that `dir` holds a complete, self-consistent `run` set for a drop
/// from rest through `gap`: the scenario, the contacts and the history are
/// of the same run. The first contact's onset is the free fall time
/// √(2 gap/g) (exact; the onset is solved exactly inside its step, so only
/// rounding separates them: 1e-9 relative is far below the ≥ 5 % between
/// the gaps used here), and the history's first row is on that free fall,
/// x = gap − g t²/2.
fn assert_run_set(dir: &Path, gap: f64) {
    assert_eq!(
        tree(dir),
        [RECORD, "contacts.csv", "history.csv", "scenario.toml"],
        "{}",
        dir.display()
    );
    let scenario: toml::Value =
        toml::from_str(&std::fs::read_to_string(dir.join("scenario.toml")).unwrap()).unwrap();
    let toml_gap = scenario["motion"]["gap"].as_float().unwrap();
    assert_eq!(toml_gap, gap, "scenario.toml is of another run");

    let mut contacts = csv::Reader::from_path(dir.join("contacts.csv")).unwrap();
    let first = contacts.records().next().unwrap().unwrap();
    let t_contact: f64 = first[1].parse().unwrap();
    let free_fall = (2.0 * gap / G).sqrt();
    assert!(
        (t_contact / free_fall - 1.0).abs() < 1e-9,
        "contacts.csv of another run: t_c = {t_contact} s, free fall {free_fall} s"
    );

    let history = std::fs::read_to_string(dir.join("history.csv")).unwrap();
    let mut lines = history.lines();
    assert_eq!(
        lines.next(),
        Some("t_s,x_m,v_m_s,a_m_s2,overlap_m,force_N,in_contact")
    );
    let first: Vec<f64> = lines
        .next()
        .unwrap()
        .split(',')
        .map(|x| x.parse().unwrap())
        .collect();
    let (t0, x0) = (first[0], first[1]);
    let fallen = gap - 0.5 * G * t0 * t0;
    assert!(
        (x0 / fallen - 1.0).abs() < 1e-9,
        "history.csv of another run: x({t0} s) = {x0} m, free fall from {gap} m gives {fallen} m"
    );
    // Complete: every row has its 7 fields, the last one included.
    assert!(history.ends_with('\n'));
    assert!(lines.all(|l| l.split(',').count() == 7));
}

/// A fixed-step run from `gap` whose history (300,000 rows, about 18 MB)
/// takes a moment to write.
fn big_run(gap: f64) -> Vec<String> {
    [
        "run",
        "--quiet",
        "--set",
        "integration.stepping=fixed",
        "--set",
        &format!("motion.gap={gap}"),
        "--history-points",
        "300000",
    ]
    .map(String::from)
    .to_vec()
}

fn strs(v: &[String]) -> Vec<&str> {
    v.iter().map(String::as_str).collect()
}

#[derive(Debug, Clone, Copy)]
enum Moment {
    /// Right after the start (before or while the staging is made).
    AtOnce,
    /// After this long.
    After(u64),
    /// As soon as the staging holds this file (the set is being written).
    Staged(&'static str),
}

fn signal_at(child: &mut Child, dir: &Path, moment: Moment, signal: &str) {
    match moment {
        Moment::AtOnce => {}
        Moment::After(ms) => std::thread::sleep(Duration::from_millis(ms)),
        Moment::Staged(file) => wait_until(child, || staging_holds(dir, file)),
    }
    send(child, signal);
}

#[test]
fn run_stopped_by_a_signal_leaves_the_whole_set_or_nothing() {
    let root = tempfile::tempdir().unwrap();
    let gap = 0.004;
    let cases = [
        (Moment::AtOnce, "TERM"),
        (Moment::After(50), "INT"),
        (Moment::Staged("scenario.toml"), "TERM"),
        (Moment::Staged("history.csv"), "INT"),
        (Moment::Staged("history.csv"), "TERM"),
        (Moment::After(400), "INT"),
        (Moment::After(800), "TERM"),
    ];
    let mut stopped_while_writing = 0;
    for (i, (moment, signal)) in cases.into_iter().enumerate() {
        // A directory that does not exist yet: the folders made for the
        // output go too.
        let base = root.path().join(format!("case{i}"));
        let dir = base.join("new/out");
        let mut child = spawn(&strs(&big_run(gap)), &dir);
        signal_at(&mut child, &dir, moment, signal);
        let code = stopped(child, signal);
        let what = format!("{moment:?} SIG{signal}, exit {code}");
        assert_eq!(leftovers(root.path()), Vec::<String>::new(), "{what}");
        if dir.exists() {
            assert_run_set(&dir, gap);
        } else {
            assert_eq!(tree(&base), Vec::<String>::new(), "{what}");
            assert_ne!(code, 0, "{what}: exit 0 without output");
            if matches!(moment, Moment::Staged(_)) {
                stopped_while_writing += 1;
            }
        }
    }
    // The signals fell in the writing at least once (the history takes a
    // few hundred ms to write; the staged file is seen within ~1 ms).
    assert!(stopped_while_writing >= 1);
}

#[test]
fn a_stopped_run_keeps_the_previous_set() {
    let root = tempfile::tempdir().unwrap();
    let dir = root.path().join("out");
    let status = spawn(&strs(&big_run(0.003)), &dir)
        .wait_with_output()
        .unwrap();
    assert!(status.status.success());
    let before: Vec<(String, Vec<u8>)> = ["scenario.toml", "contacts.csv", "history.csv"]
        .iter()
        .map(|n| (n.to_string(), std::fs::read(dir.join(n)).unwrap()))
        .collect();
    for (moment, signal) in [
        (Moment::Staged("history.csv"), "INT"),
        (Moment::Staged("contacts.csv"), "TERM"),
    ] {
        let mut child = spawn(&strs(&big_run(0.004)), &dir);
        signal_at(&mut child, &dir, moment, signal);
        let code = stopped(child, signal);
        assert_eq!(leftovers(root.path()), Vec::<String>::new());
        if code == 0 {
            assert_run_set(&dir, 0.004);
            return;
        }
        assert_run_set(&dir, 0.003);
        for (name, bytes) in &before {
            assert!(
                std::fs::read(dir.join(name)).unwrap() == *bytes,
                "{name} changed"
            );
        }
    }
}

/// The files `paper` writes, as the record lists them, are all there, and
/// the reports and paper.json are whole.
fn assert_paper_set(dir: &Path) {
    let record: serde_json::Value =
        serde_json::from_slice(&std::fs::read(dir.join(RECORD)).unwrap()).unwrap();
    let mut listed: Vec<String> = record["sets"]["paper"]
        .as_array()
        .unwrap()
        .iter()
        .map(|v| v.as_str().unwrap().to_string())
        .collect();
    listed.push(RECORD.into());
    listed.push("restitution".into());
    listed.sort();
    assert_eq!(tree(dir), listed);
    for f in ["4a", "5b", "8b"] {
        assert!(listed.contains(&format!("fig{f}.png")), "{listed:?}");
    }
    let json: serde_json::Value =
        serde_json::from_slice(&std::fs::read(dir.join("paper.json")).unwrap()).unwrap();
    assert!(json.is_object());
    let html = std::fs::read_to_string(dir.join("report.html")).unwrap();
    assert!(html.trim_end().ends_with("</html>"));
    let md = std::fs::read_to_string(dir.join("report.md")).unwrap();
    for line in md.lines().filter(|l| l.starts_with("![")) {
        let target = line.split("](").nth(1).unwrap().trim_end_matches(')');
        assert!(dir.join(target).is_file(), "{target} of report.md missing");
    }
}

#[test]
fn paper_stopped_by_a_signal_leaves_the_whole_set_or_nothing() {
    // `paper` computes for seconds: two runs, each cut short, one while
    // computing and one while drawing the figures into the staging (the
    // moments next to publishing are covered by `run` above, through the
    // same code).
    let root = tempfile::tempdir().unwrap();
    let cases = [
        (Moment::After(300), "INT"),
        (Moment::Staged("fig4a.png"), "TERM"),
    ];
    let mut stopped_while_writing = 0;
    for (i, (moment, signal)) in cases.into_iter().enumerate() {
        let dir = root.path().join(format!("paper{i}"));
        let mut child = spawn(&["paper", "--quiet"], &dir);
        signal_at(&mut child, &dir, moment, signal);
        let code = stopped(child, signal);
        let what = format!("{moment:?} SIG{signal}, exit {code}");
        assert_eq!(leftovers(root.path()), Vec::<String>::new(), "{what}");
        if dir.exists() {
            assert_paper_set(&dir);
        } else {
            assert_ne!(code, 0, "{what}: exit 0 without output");
            if matches!(moment, Moment::Staged(_)) {
                stopped_while_writing += 1;
            }
        }
    }
    assert!(stopped_while_writing >= 1);
}

#[test]
fn concurrent_writers_each_leave_a_consistent_set() {
    let root = tempfile::tempdir().unwrap();
    let dir = root.path().join("shared");
    let gaps = [0.002, 0.0025, 0.003, 0.0035];
    for round in 0..3 {
        let children: Vec<Child> = gaps
            .iter()
            .map(|&gap| {
                let mut args = big_run(gap);
                *args.last_mut().unwrap() = "100000".into();
                spawn(&strs(&args), &dir)
            })
            .collect();
        for child in children {
            let out = child.wait_with_output().unwrap();
            assert!(
                out.status.success(),
                "{}",
                String::from_utf8_lossy(&out.stderr)
            );
        }
        let scenario: toml::Value =
            toml::from_str(&std::fs::read_to_string(dir.join("scenario.toml")).unwrap()).unwrap();
        let gap = scenario["motion"]["gap"].as_float().unwrap();
        assert!(gaps.contains(&gap), "round {round}: gap {gap}");
        assert_run_set(&dir, gap);
        assert_eq!(leftovers(root.path()), Vec::<String>::new());
    }
}

#[test]
fn a_bad_out_is_refused_before_computing() {
    let root = tempfile::tempdir().unwrap();
    let file = root.path().join("a-file");
    std::fs::write(&file, "mine").unwrap();
    let mut targets: Vec<(PathBuf, &str)> = vec![
        (file.clone(), "is not a directory"),
        (file.join("sub"), "not a directory"),
    ];
    // A place nobody may create folders in (chmod does not stop root).
    #[cfg(target_os = "linux")]
    targets.push((PathBuf::from("/proc/dembound-test-out"), "cannot create"));
    let read_only = root.path().join("read-only");
    std::fs::create_dir(&read_only).unwrap();
    {
        use std::os::unix::fs::PermissionsExt;
        std::fs::set_permissions(&read_only, std::fs::Permissions::from_mode(0o555)).unwrap();
    }
    let probe = read_only.join("probe");
    if std::fs::write(&probe, "").is_err() {
        targets.push((read_only.join("out"), "Permission denied"));
    } else {
        std::fs::remove_file(&probe).unwrap();
    }
    // Each of these computes for seconds when it starts (paper ~5 s of
    // CPU, validate ~4.5 s, the fixed-step run ~0.5 s).
    let commands: [&[&str]; 5] = [
        &["run", "--set", "integration.stepping=fixed", "--quiet"],
        &["paper"],
        &["validate"],
        &["sweep", "--r", "1,10", "--zeta", "1,10", "--plot"],
        &["restitution", "--law", "viscous", "--e", "0.5"],
    ];
    for args in commands {
        for (target, why) in &targets {
            let start = Instant::now();
            let out = dembound()
                .args(args)
                .arg("--out")
                .arg(target)
                .output()
                .unwrap();
            let elapsed = start.elapsed();
            let stderr = String::from_utf8_lossy(&out.stderr);
            let what = format!("{args:?} --out {}", target.display());
            assert_eq!(out.status.code(), Some(2), "{what}: {stderr}");
            assert!(
                stderr.starts_with("error: --out `")
                    && stderr.contains(&*target.to_string_lossy())
                    && stderr.contains(why),
                "{what}: {stderr}"
            );
            // Nothing else on stderr (`paper` reports each stage there).
            assert_eq!(stderr.lines().count(), 1, "{what}: {stderr}");
            assert!(out.stdout.is_empty(), "{what}");
            // Refused in milliseconds; 1.5 s leaves room for a loaded
            // machine and is well below the computations above.
            assert!(elapsed < Duration::from_millis(1500), "{what}: {elapsed:?}");
        }
    }
    assert_eq!(std::fs::read_to_string(&file).unwrap(), "mine");
    assert_eq!(tree(root.path()), ["a-file", "read-only"]);
}

#[test]
fn a_failed_publish_keeps_the_previous_set_whole() {
    let root = tempfile::tempdir().unwrap();
    // A directory where `run` wants contacts.csv: nothing else appears.
    let dir = root.path().join("run");
    std::fs::create_dir_all(dir.join("contacts.csv")).unwrap();
    let out = dembound()
        .args(["run", "--quiet", "--out"])
        .arg(&dir)
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{stderr}");
    assert!(stderr.contains("contacts.csv"), "{stderr}");
    assert_eq!(tree(&dir), ["contacts.csv"]);

    // A previous restitution set survives a failed one whole.
    let dir = root.path().join("restitution");
    let study = |r: &str| {
        dembound()
            .args([
                "restitution",
                "--law",
                "viscous",
                "--e",
                "0.5",
                "--zeta",
                "1,inf",
            ])
            .args(["--r", r, "--out"])
            .arg(&dir)
            .output()
            .unwrap()
    };
    assert!(study("1,inf").status.success());
    let snapshot = |dir: &Path| -> Vec<(String, Vec<u8>)> {
        tree(dir)
            .into_iter()
            .map(|p| {
                let bytes = std::fs::read(dir.join(&p)).unwrap_or_default();
                (p, bytes)
            })
            .collect()
    };
    std::fs::remove_file(dir.join("restitution.md")).unwrap();
    std::fs::create_dir(dir.join("restitution.md")).unwrap();
    let before = snapshot(&dir);
    assert!(before.len() > 8, "{:?}", tree(&dir));
    let out = study("1,10,inf");
    assert_eq!(out.status.code(), Some(1));
    assert!(snapshot(&dir) == before, "the previous set changed");
    assert_eq!(leftovers(root.path()), Vec::<String>::new());
}

#[test]
fn a_new_set_removes_the_previous_sets_files_and_keeps_the_users() {
    let root = tempfile::tempdir().unwrap();
    let dir = root.path();
    std::fs::write(dir.join("notes.txt"), "mine").unwrap();
    let sweep = |plot: bool| {
        let mut cmd = dembound();
        cmd.args(["sweep", "--r", "1,10", "--zeta", "1,10", "--quiet", "--out"])
            .arg(dir);
        if plot {
            cmd.arg("--plot");
        }
        assert!(cmd.output().unwrap().status.success());
    };
    sweep(true);
    assert!(tree(dir).iter().any(|n| n.ends_with(".png")));
    sweep(false);
    assert_eq!(tree(dir), [RECORD, "notes.txt", "sweep.csv", "sweep.json"]);
}
