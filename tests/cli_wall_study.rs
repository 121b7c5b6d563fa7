//! `dembound wall-study` (issue 13), through the real binary: the quick
//! study writes every promised file at once; bad input exits 2 naming the
//! option and writes nothing.

mod common;

use common::dembound;

#[test]
fn quick_study_writes_its_files() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("study");
    let run = dembound()
        .args(["wall-study", "--quick", "--quiet", "--out"])
        .arg(&out)
        .output()
        .unwrap();
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    for f in [
        "impacts.csv",
        "summary.csv",
        "profile.csv",
        "boundary_forces.csv",
        "report.md",
        "restitution.svg",
        "restitution.png",
        "contact_time.png",
        "packing_profile.png",
        "bed_side.svg",
        "bed_side.png",
        "chute.csv",
        "chute_profile.svg",
        "chute_profile.png",
    ] {
        assert!(out.join(f).is_file(), "{f} missing");
    }
    let report = std::fs::read_to_string(out.join("report.md")).unwrap();
    assert!(report.contains("## Recommendation"));
    assert!(report.contains("## Chute flow"));
    // r = 100 touching spheres leave gaps a particle falls through: no chute.
    assert!(report.contains("not run: not a wall"));
    assert!(report.contains("r=100 zeta=100 square"));
    // The settled bed's floor carries its weight on every floor: the
    // summary's floor pressure within 1 % of the weight per area (0.05 s
    // of settling after the pour; the residual motion is ~1e-3 g).
    let summary = std::fs::read_to_string(out.join("summary.csv")).unwrap();
    let weight: f64 = report
        .split("weight per area (")
        .nth(1)
        .and_then(|s| s.split(' ').next())
        .and_then(|s| s.parse().ok())
        .unwrap();
    let mut floors = 0;
    for line in summary
        .lines()
        .filter(|l| l.contains("floor pressure (Pa)"))
    {
        let p: f64 = line.split(',').nth(2).unwrap().parse().unwrap();
        assert!((p / weight - 1.0).abs() < 0.01, "{line} vs {weight} Pa");
        floors += 1;
    }
    assert_eq!(floors, 3);
}

#[test]
fn bad_input_exits_2_and_writes_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("study");
    for (args, key) in [
        (vec!["--radius-ratios", "0.1"], "--radius-ratios"),
        (vec!["--tilings", "round"], "--tilings"),
        (vec!["--friction=-1"], "--friction"),
        (vec!["--tangential", "hooke"], "--tangential"),
        (vec!["--angles", "95"], "--angles"),
        (vec!["--chute-angle", "95"], "--chute-angle"),
        (vec!["--chute-layers", "0.5"], "--chute-layers"),
        (vec!["--floor-friction=-1"], "--floor-friction"),
    ] {
        let run = dembound()
            .args(["wall-study", "--quick", "--quiet", "--out"])
            .arg(&out)
            .args(&args)
            .output()
            .unwrap();
        assert_eq!(run.status.code(), Some(2), "{args:?}");
        let err = String::from_utf8_lossy(&run.stderr);
        assert!(err.contains(key), "{args:?}: {err}");
        assert!(!out.exists(), "{args:?} wrote output");
    }
}
