//! The benchmark families of `tests/common/families.rs` (a TX-90 of `../shared/robots`
//! among generated obstacles): each problem's world built once, then what `compile`
//! does between loading and writing (plan, schedule, verify), timed per problem.
//! Skipped when `../shared/robots` is absent.
//!
//! `RAYON_NUM_THREADS=1 cargo bench --bench families` (one core); `FAMILY_N` problems
//! per family (default 5).

use std::path::Path;

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion};
use declutter::diag::{FsLoader, SourceMap};
use declutter::world::{self, WorldOptions};

#[path = "../tests/common/families.rs"]
mod families;

fn bench_families(c: &mut Criterion) {
    let Some(robots) = families::shared_robots() else { return };
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("bench-families");
    std::fs::create_dir_all(&dir).expect("scratch dir");
    let arm = families::Arm::Tx90;
    let probe = families::probe(arm, &robots, &dir).expect("the arm builds");
    let n: u64 = std::env::var("FAMILY_N").ok().and_then(|v| v.parse().ok()).unwrap_or(5);
    let mut group = c.benchmark_group("families");
    group.sample_size(10);
    for family in families::FAMILIES {
        for i in 0..n {
            let p = families::problem(arm, &probe, &robots, &dir, family, i).expect("a goal is found");
            let mut sources = SourceMap::new();
            let scn = declutter::resolve::resolve(&p.path, &FsLoader, &mut sources).expect("resolves");
            let w = world::build(&scn, &WorldOptions::default(), &FsLoader).expect("builds");
            group.bench_with_input(BenchmarkId::new(family, i), &w, |b, w| {
                b.iter(|| declutter::driver::plan_verified(w, &|_| {}).map(|p| p.schedule.actions.len()).ok())
            });
        }
    }
    group.finish();
}

criterion_group!(benches, bench_families);
criterion_main!(benches);
