//! The benchmark families of `tests/common/families.rs` (the arms of `../shared/robots`
//! among generated obstacles), timed per problem end to end as the issue measures them:
//! from the written scenario to a verified schedule (resolve, world build, plan,
//! schedule, verify). Skipped when `../shared/robots` is absent.
//!
//! `RAYON_NUM_THREADS=1 cargo bench --bench families` (one core); `FAMILY_N` problems
//! per arm and family (default 2), `FAMILY_ARMS=Tx90,Ur5` for some arms only. The
//! solved fraction, median and 95th percentile over the problems known to have a path
//! are measured by `benches/families_known.rs`.

use std::path::Path;

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion};

#[path = "../tests/common/families.rs"]
mod families;

/// Load to verified schedule; the number of actions, or `None` if it went wrong.
fn end_to_end(path: &Path) -> Option<usize> {
    families::compile(path).map(|p| p.schedule.actions.len()).ok()
}

fn bench_families(c: &mut Criterion) {
    let Some(robots) = families::shared_robots() else { return };
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("bench-families");
    std::fs::create_dir_all(&dir).expect("scratch dir");
    let n: u64 = std::env::var("FAMILY_N").ok().and_then(|v| v.parse().ok()).unwrap_or(2);
    let only = std::env::var("FAMILY_ARMS").ok();
    let mut group = c.benchmark_group("families");
    group.sample_size(10);
    for arm in families::ARMS {
        if only.as_ref().is_some_and(|o| !o.split(',').any(|a| a == format!("{arm:?}"))) {
            continue;
        }
        let probe = families::probe(arm, &robots, &dir).expect("the arm builds");
        for family in families::FAMILIES {
            for i in 0..n {
                let Some(p) = families::problem(arm, &probe, &robots, &dir, family, i) else { continue };
                group.bench_with_input(BenchmarkId::new(format!("{arm:?}/{family}"), i), &p.path, |b, path| {
                    b.iter(|| end_to_end(path))
                });
            }
        }
    }
    group.finish();
}

criterion_group!(benches, bench_families);
criterion_main!(benches);
