//! The replay in time on the shipped two-arm shelf, its planned (untimed) schedule given
//! times by a simple stand-in for the timing stage: one action at a time verifies; both
//! arms started at once collide, and the report names both robots, their bodies and the
//! time.

mod time_support;

use std::path::Path;

use declutter::diag::{FsLoader, SourceMap};
use declutter::plan::{andor, Planner};
use declutter::schedule::{self, Schedule};
use declutter::verify::time::{replay, Obstacle, Party, RateLimits, ReplayOptions, TimeViolation, SAMPLE_BOUND};
use declutter::verify::{Location, ViolationKind};
use declutter::world::{self, World, WorldOptions};

fn compiled(file: &str) -> (World, Schedule) {
    let mut sources = SourceMap::new();
    let scn = declutter::resolve::resolve(Path::new(file), &FsLoader, &mut sources).expect("example resolves");
    let w = world::build(&scn, &WorldOptions::default(), &FsLoader).expect("example world builds");
    let planner = Planner::new(&w, &w.scenario().planner);
    let sol = andor::solve(w.scenario(), &planner);
    let s = schedule::build(w.scenario(), &sol);
    (w, s)
}

fn options(w: &World) -> ReplayOptions {
    let velocity = w
        .scenario()
        .robots
        .iter()
        .enumerate()
        .map(|(r, _)| vec![1.0; w.dof(declutter::resolve::RobotId(r as u32))])
        .collect();
    ReplayOptions { bound: SAMPLE_BOUND, clearance: 0.0, limits: RateLimits { velocity, acceleration: 3.0 } }
}

#[test]
fn shelf_one_action_at_a_time_verifies_and_both_arms_at_once_collide() {
    let (w, s) = compiled("examples/shelf.dcl");
    let robots: Vec<&str> = s.actions.iter().map(|a| a.robot.as_str()).collect();
    assert!(robots.contains(&"r1") && robots.contains(&"r2"), "{robots:?}");

    let tl = time_support::naive_timeline(&w, &s, 1.0, 3.0, false);
    let (summary, v) = replay(&w, &tl, &options(&w));
    assert!(v.is_empty(), "{v:#?}");
    assert!(summary.samples > 1000, "{summary:?}");
    // An independent re-check at a quarter of the verifier's bound agrees.
    assert!(time_support::dense_contacts(&w, &tl, SAMPLE_BOUND / 4.0).is_empty());

    let tl = time_support::naive_timeline(&w, &s, 1.0, 3.0, true);
    let (_, v) = replay(&w, &tl, &options(&w));
    let contact = v
        .iter()
        .find_map(|v| match (&v.location, &v.kind) {
            (
                Location::At { t },
                ViolationKind::Time(TimeViolation::Contact {
                    a: Party::Body { robot, body },
                    b:
                        Obstacle::Moving(
                            Party::Body { robot: other, body: other_body }
                            | Party::Held { robot: other, object: other_body },
                        ),
                    ..
                }),
            ) if robot != other => {
                Some((*t, robot.clone(), body.clone(), other.clone(), other_body.clone(), v.to_string()))
            }
            _ => None,
        })
        .unwrap_or_else(|| panic!("no robot–robot contact in {v:#?}"));
    let (t, a, _, b, _, text) = contact;
    assert!(t > 0.0 && t < tl.makespan);
    assert_eq!((a.as_str(), b.as_str()), ("r1", "r2"));
    assert!(text.starts_with("t = ") && text.contains("robot `r1` body `") && text.contains("robot `r2`"), "{text}");
}
