//! Two workers of the team held on one core (what a busy machine does when
//! another process takes the second core): each stage needs both, so the
//! core must pass from the worker that waits to the one it waits for. A
//! worker that spins long before it yields burns the core meanwhile: with
//! 2^14 spins before yielding (424 µs on the AMD EPYC of BENCHMARKS.md,
//! 25.9 ns a spin) a stage cost two such spins, ~0.85 ms of CPU, and two
//! threads on one core ran the 10k lattice drop ~20× slower than one
//! thread. This test holds its process on one core (`sched_setaffinity`;
//! the team's threads inherit it) and measures the CPU time the process
//! spends per stage of a team whose job is nothing: all of it is the
//! hand-offs. Its own test binary, so that no other test's threads add to
//! the process's CPU time.

use std::time::Instant;

use dembound_scene::parallel::Workers;

/// Holds the calling thread (and the threads it starts afterwards) on the
/// first core it may run on; false if the kernel refuses.
fn hold_on_one_core() -> bool {
    // SAFETY: a zeroed cpu_set_t is the empty set; the calls get and set
    // the calling thread's own mask with the set's true size.
    unsafe {
        let mut set: libc::cpu_set_t = std::mem::zeroed();
        let size = std::mem::size_of::<libc::cpu_set_t>();
        if libc::sched_getaffinity(0, size, &mut set) != 0 {
            return false;
        }
        let Some(cpu) = (0..libc::CPU_SETSIZE as usize).find(|&c| libc::CPU_ISSET(c, &set)) else {
            return false;
        };
        let mut one: libc::cpu_set_t = std::mem::zeroed();
        libc::CPU_SET(cpu, &mut one);
        libc::sched_setaffinity(0, size, &one) == 0
    }
}

/// CPU time of the whole process so far, s.
fn process_cpu_seconds() -> f64 {
    let mut t = libc::timespec {
        tv_sec: 0,
        tv_nsec: 0,
    };
    // SAFETY: `t` is a valid timespec to write.
    let ok = unsafe { libc::clock_gettime(libc::CLOCK_PROCESS_CPUTIME_ID, &mut t) } == 0;
    assert!(ok, "clock_gettime(CLOCK_PROCESS_CPUTIME_ID) failed");
    t.tv_sec as f64 + t.tv_nsec as f64 * 1e-9
}

/// CPU time of `n` spins (`spin_loop`, the waits' spin) on this machine, s.
/// A spin's cost differs by a factor of several between processors (PAUSE
/// is a few cycles on AMD Zen, ~140 on recent Intel cores), so the bound
/// below is set from this machine's own spin rather than a fixed time.
fn spin_cpu_seconds(n: u32) -> f64 {
    let start = process_cpu_seconds();
    for _ in 0..n {
        std::hint::spin_loop();
    }
    process_cpu_seconds() - start
}

/// Empty stages of a two-worker team on one core cost little CPU each:
/// the waiting worker hands the core over after a short spin. A stage
/// has two waits; with 2^10 spins before yielding each costs at most the
/// CPU of 2^10 spins (timed here, the minimum of 20 tries, so a
/// descheduled try does not inflate it) plus a context switch. The bound
/// is four such spins plus 150 µs for the switches and the stage itself
/// (~60 µs measured in all on the AMD EPYC of BENCHMARKS.md, where a
/// spin is 25.9 ns: bound ~256 µs): twice the two waits, room for a loaded
/// machine's switches. With 2^14 spins a stage costs two 2^14-spin waits,
/// 32 × 2^10 spins (~850 µs there), beyond the bound on any processor
/// whose 2^10 spins take more than ~10 µs; the test fails then.
#[test]
fn two_workers_on_one_core_hand_the_core_over_quickly() {
    assert!(hold_on_one_core(), "sched_setaffinity refused one core");
    // Timed before the team starts: no worker shares the core yet.
    let spins_1024 = (0..20)
        .map(|_| spin_cpu_seconds(1 << 10))
        .fold(f64::INFINITY, f64::min);
    let bound = 4.0 * spins_1024 + 150e-6;
    let workers = Workers::new(2).expect("two workers start");
    let stage = || {
        let ids = workers.broadcast(|t| t);
        assert_eq!(ids, vec![0, 1]);
    };
    // The worker thread started and past its first park.
    for _ in 0..20 {
        stage();
    }
    let stages = 500;
    let (cpu, wall) = (process_cpu_seconds(), Instant::now());
    for _ in 0..stages {
        stage();
    }
    let per_stage = (process_cpu_seconds() - cpu) / stages as f64;
    let wall = wall.elapsed().as_secs_f64() / stages as f64;
    eprintln!(
        "two workers on one core: {:.1} µs CPU, {:.1} µs wall a stage; 2^10 spins {:.1} µs, bound {:.1} µs",
        per_stage * 1e6,
        wall * 1e6,
        spins_1024 * 1e6,
        bound * 1e6
    );
    assert!(
        per_stage < bound,
        "{:.1} µs of CPU a stage on one core (bound {:.1} µs)",
        per_stage * 1e6,
        bound * 1e6
    );
}
