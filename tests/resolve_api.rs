//! The resolver's conventions, checked through its API on in-memory files.

use std::f64::consts::{FRAC_PI_2, PI};
use std::path::Path;

use nalgebra::{UnitQuaternion, Vector3};

use declutter::diag::{Located, MemLoader, SourceMap};
use declutter::resolve::{self, Objective, Shape, Target};
use declutter::syntax::{self, ast};

const CELL: &str = r#"
hand h { urdf "h.urdf" tcp at (0, 0, 10cm) }
robot r { urdf "r.urdf" hand h home [0, 0, 0] }
"#;

fn loader(root: &str) -> MemLoader {
    MemLoader::new()
        .with("cell/cell.dcl", CELL)
        .with("cell/h.urdf", "<robot/>")
        .with("cell/r.urdf", "<robot/>")
        .with("cell/m.stl", "solid m\nendsolid m\n")
        .with("root.dcl", root)
}

fn resolve(root: &str) -> Result<resolve::Scenario, Vec<String>> {
    let l = loader(root);
    let mut sources = SourceMap::new();
    resolve::resolve(Path::new("root.dcl"), &l, &mut sources)
        .map_err(|errs| errs.iter().map(|e| e.code_str()).collect())
}

#[test]
fn rotations_are_fixed_axis_rpy_like_urdf() {
    let s = resolve(
        r#"use "cell/cell.dcl"
           object o box(1cm, 1cm, 1cm) at (1, 2, 3) rot (10deg, 20deg, 30deg)
           target o"#,
    )
    .unwrap();
    let q = s.objects[0].body.pose_world_body.rotation;
    let (r, p, y) = (10f64.to_radians(), 20f64.to_radians(), 30f64.to_radians());
    let rz = UnitQuaternion::from_axis_angle(&Vector3::z_axis(), y);
    let ry = UnitQuaternion::from_axis_angle(&Vector3::y_axis(), p);
    let rx = UnitQuaternion::from_axis_angle(&Vector3::x_axis(), r);
    assert!(q.angle_to(&(rz * ry * rx)) < 1e-12);
    assert_eq!(s.objects[0].body.pose_world_body.translation.vector, Vector3::new(1.0, 2.0, 3.0));
}

#[test]
fn parts_and_grasps_compose_with_the_body_pose() {
    let s = resolve(
        r#"use "cell/cell.dcl"
           object o at (1m, 0, 0) rot (0, 0, 90deg) {
               sphere(radius: 1cm) at (10cm, 0, 0)
               grasp g at (0, 5cm, 0) repeat 2 about x approach 2cm
           }
           target o"#,
    )
    .unwrap();
    let o = &s.objects[0];
    let part = o.body.parts[0].pose_world_part.translation.vector;
    assert!((part - Vector3::new(1.0, 0.1, 0.0)).norm() < 1e-12);
    assert_eq!(o.grasps.iter().map(|g| g.name.as_str()).collect::<Vec<_>>(), ["g#0", "g#1"]);
    // Copy 1 is turned half a turn about the object's x: (0, 5cm, 0) -> (0, -5cm, 0),
    // then the body's quarter turn about z maps the object's -y to the world's +x.
    let g1 = o.grasps[1].pose_world_tcp.translation.vector;
    assert!((g1 - Vector3::new(1.05, 0.0, 0.0)).norm() < 1e-12, "{g1}");
    assert!((o.grasps[1].approach - 0.02).abs() < 1e-15);
    let rot = o.grasps[1].pose_object_tcp.rotation;
    assert!((rot.angle() - PI).abs() < 1e-12);
}

#[test]
fn units_and_planner_settings() {
    let s = resolve(
        r#"use "cell/cell.dcl"
           planner { seed 9 resolution 0.01 time_budget 250ms objective fewest_vertices neighbours 3 first_path true max_samples 7 }
           object o cylinder(15mm, 0.2m) at (0, 0, 0)
           target r at [90deg, 1, 5cm]"#,
    )
    .unwrap();
    assert_eq!(s.planner.seed, 9);
    assert_eq!(s.planner.max_samples, 7);
    assert_eq!(s.planner.neighbours, 3);
    assert!(s.planner.first_path);
    assert_eq!(s.planner.objective, Objective::FewestVertices);
    assert!((s.planner.resolution - 0.01).abs() < 1e-15);
    assert!((s.planner.time_budget.unwrap() - 0.25).abs() < 1e-15);
    assert_eq!(s.objects[0].body.parts[0].shape, Shape::Cylinder { radius: 0.015, length: 0.2 });
    match &s.target {
        Target::Config { q, .. } => {
            assert!((q.values[0] - FRAC_PI_2).abs() < 1e-15);
            assert_eq!(q.values[1..], [1.0, 0.05]);
        }
        t => panic!("{t:?}"),
    }
    assert!((s.hands[0].pose_flange_tcp.translation.z - 0.1).abs() < 1e-15);
    assert_eq!(s.robots[0].urdf.path, Path::new("cell/r.urdf"));
}

#[test]
fn root_planner_overrides_a_used_files() {
    let l = loader("use \"cell/p.dcl\"\nplanner { seed 5 }\nobject o sphere(1cm)\ntarget o")
        .with("cell/p.dcl", format!("{CELL}\nplanner {{ seed 3 max_samples 10 }}"));
    let mut sources = SourceMap::new();
    let s = resolve::resolve(Path::new("root.dcl"), &l, &mut sources).unwrap();
    assert_eq!((s.planner.seed, s.planner.max_samples), (5, 10));
}

#[test]
fn a_diamond_is_loaded_once() {
    let l = loader("use \"a.dcl\"\nuse \"b.dcl\"\ntarget oa")
        .with("a.dcl", "use \"cell/cell.dcl\"\nobject oa sphere(1cm)")
        .with("b.dcl", "use \"./cell/../cell/cell.dcl\"\nobject ob sphere(1cm)");
    let mut sources = SourceMap::new();
    let s = resolve::resolve(Path::new("root.dcl"), &l, &mut sources).unwrap();
    assert_eq!(s.robots.len(), 1);
    assert_eq!(sources.files().count(), 4);
}

#[test]
fn errors_are_collected_and_sorted() {
    let l = loader(
        "use \"cell/cell.dcl\"\nobject a box(1deg, 1, 1)\nobject b sphere(-1)\nobject c sphere(1) { grasp g at (0, 0) }\ntarget zz",
    );
    let mut sources = SourceMap::new();
    let errs = resolve::resolve(Path::new("root.dcl"), &l, &mut sources).unwrap_err();
    let codes: Vec<String> = errs.iter().map(|e| e.code_str()).collect();
    assert_eq!(
        codes,
        [
            "declutter::resolve::unit_mismatch",
            "declutter::resolve::out_of_range",
            "declutter::resolve::wrong_count",
            "declutter::resolve::unknown_name"
        ]
    );
    let spans: Vec<_> = errs.iter().map(|e| e.primary_span().unwrap()).collect();
    assert!(spans.windows(2).all(|w| w[0] <= w[1]));
}

#[test]
fn a_library_checks_but_does_not_resolve() {
    let l = loader("use \"cell/cell.dcl\"\nobject o sphere(1cm)");
    let mut sources = SourceMap::new();
    let summary = resolve::check(Path::new("root.dcl"), &l, &mut sources).unwrap();
    assert!(summary.library);
    assert_eq!((summary.robots, summary.objects), (1, 1));
    assert_eq!(
        resolve("use \"cell/cell.dcl\"\nobject o sphere(1cm)").unwrap_err(),
        ["declutter::resolve::missing_target"]
    );
    // A `scenario` line makes it a scenario, which needs a target.
    let l = loader("scenario \"s\"\nuse \"cell/cell.dcl\"\nobject o sphere(1cm)");
    let mut sources = SourceMap::new();
    assert!(resolve::check(Path::new("root.dcl"), &l, &mut sources).is_err());
}

#[test]
fn syntax_spans_are_exact() {
    let text = "fixed t box(1, 2, 3cm)   // a comment\n   at (0, 0, 0) // another\n\nhand h { urdf \"a\\\"b.urdf\" }";
    let f = syntax::parse(declutter::diag::FileId(0), text).unwrap();
    let ast::Item::Body(b) = &f.items[0] else { panic!() };
    let span_text = |s: declutter::diag::Span| &text[s.start as usize..s.end as usize];
    assert_eq!(span_text(b.span), "fixed t box(1, 2, 3cm)   // a comment\n   at (0, 0, 0)");
    let shape = b.shape.as_ref().unwrap();
    assert_eq!(span_text(shape.span), "box(1, 2, 3cm)");
    assert_eq!(span_text(shape.args_span), "(1, 2, 3cm)");
    let ast::ArgValue::Quantity(q) = &shape.args[2].value else { panic!() };
    assert_eq!((q.value, q.unit.as_ref().unwrap().name.as_str()), (3.0, "cm"));
    let ast::Item::Hand(h) = &f.items[1] else { panic!() };
    let ast::HandItem::Urdf { path, .. } = &h.items[0] else { panic!() };
    assert_eq!(path.value, "a\"b.urdf");
    assert_eq!(span_text(h.span), "hand h { urdf \"a\\\"b.urdf\" }");
}

/// 100 grasps x `repeat 10000` once took 1.3 s and 346 MB to resolve (and `check` hung):
/// the expansion limits stop it at the first `repeat` over the line.
#[test]
fn grasp_expansion_is_limited_per_object_and_in_total() {
    let started = std::time::Instant::now();
    let many: String = (0..100).map(|i| format!("grasp g{i} at (0, 0, 0) repeat 10000 about z\n")).collect();
    let errs =
        resolve(&format!("use \"cell/cell.dcl\"\nobject o sphere(radius: 1cm) {{\n{many}}}\ntarget o")).unwrap_err();
    assert_eq!(errs, ["declutter::resolve::out_of_range"]);
    // 11 objects of 1000 grasps each: each is within its own limit, the total is not.
    let objects: String = (0..11)
        .map(|i| format!("object o{i} sphere(radius: 1cm) {{ grasp g at (0, 0, 0) repeat 1000 about z }}\n"))
        .collect();
    let errs = resolve(&format!("use \"cell/cell.dcl\"\n{objects}target o0")).unwrap_err();
    assert_eq!(errs, ["declutter::resolve::out_of_range"]);
    assert!(started.elapsed().as_secs_f64() < 2.0, "took {:?}", started.elapsed());
    // At the limits it is fine.
    let objects: String = (0..10)
        .map(|i| format!("object o{i} sphere(radius: 1cm) {{ grasp g at (0, 0, 0) repeat 1000 about z }}\n"))
        .collect();
    let s = resolve(&format!("use \"cell/cell.dcl\"\n{objects}target o0")).unwrap();
    assert_eq!(s.objects.iter().map(|o| o.grasps.len()).sum::<usize>(), 10_000);
}

/// A root file with objects of its own but no target is still a valid library, with a
/// warning; a cell file (robots and hands only) gets none.
#[test]
fn objects_without_a_target_warn() {
    let l = loader("use \"cell/cell.dcl\"\nobject o sphere(radius: 1cm)\n");
    let mut sources = SourceMap::new();
    let s = resolve::check(Path::new("root.dcl"), &l, &mut sources).unwrap();
    assert!(s.library);
    let codes: Vec<String> = s.warnings.iter().map(|w| w.code_str()).collect();
    assert_eq!(codes, ["declutter::resolve::no_target"]);
    assert_eq!(s.warnings[0].primary_span().map(|sp| sp.file), Some(declutter::diag::FileId(0)));
    let mut sources = SourceMap::new();
    let s = resolve::check(Path::new("cell/cell.dcl"), &l, &mut sources).unwrap();
    assert!(s.library && s.warnings.is_empty());
}
