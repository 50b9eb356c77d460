#![allow(dead_code)] // Shared by the benches; each uses only the clocks it needs.
//! A criterion measurement by CPU time rather than wall time: on a shared machine the
//! wall clock also counts the time a thread waits for a core, the CPU clock does not.

use criterion::measurement::{Measurement, ValueFormatter};
use criterion::Throughput;

/// CPU time of one clock: this thread's (`CLOCK_THREAD_CPUTIME_ID`) for work done on
/// the benchmark thread, or the whole process's (`CLOCK_PROCESS_CPUTIME_ID`) for work
/// spread over rayon's workers (run those with `RAYON_NUM_THREADS=1` for one core).
pub struct CpuTime {
    clock: libc::clockid_t,
    unit: Unit,
}

impl CpuTime {
    pub fn thread() -> Self {
        CpuTime { clock: libc::CLOCK_THREAD_CPUTIME_ID, unit: Unit { div: 1e3, name: "µs (thread CPU)" } }
    }
    pub fn process() -> Self {
        CpuTime { clock: libc::CLOCK_PROCESS_CPUTIME_ID, unit: Unit { div: 1e6, name: "ms (process CPU)" } }
    }
    pub fn now_ns(&self) -> u64 {
        let mut t = libc::timespec { tv_sec: 0, tv_nsec: 0 };
        // SAFETY: `t` is a valid timespec the call writes into.
        let rc = unsafe { libc::clock_gettime(self.clock, &mut t) };
        assert_eq!(rc, 0, "clock_gettime failed");
        t.tv_sec as u64 * 1_000_000_000 + t.tv_nsec as u64
    }
}

struct Unit {
    div: f64,
    name: &'static str,
}

impl ValueFormatter for Unit {
    fn scale_values(&self, _typical: f64, values: &mut [f64]) -> &'static str {
        values.iter_mut().for_each(|v| *v /= self.div);
        self.name
    }
    fn scale_throughputs(&self, _typical: f64, _t: &Throughput, _values: &mut [f64]) -> &'static str {
        "ns"
    }
    fn scale_for_machines(&self, _values: &mut [f64]) -> &'static str {
        "ns"
    }
}

impl Measurement for CpuTime {
    type Intermediate = u64;
    type Value = u64;
    fn start(&self) -> u64 {
        self.now_ns()
    }
    fn end(&self, i: u64) -> u64 {
        self.now_ns().saturating_sub(i)
    }
    fn add(&self, a: &u64, b: &u64) -> u64 {
        a + b
    }
    fn zero(&self) -> u64 {
        0
    }
    fn to_f64(&self, v: &u64) -> f64 {
        *v as f64
    }
    fn formatter(&self) -> &dyn ValueFormatter {
        &self.unit
    }
}
