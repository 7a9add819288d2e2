//! Objects compiled apart and posed per frame (`peel_runtime::place`): their id images against
//! the ray-casting reference of the posed triangles, over many poses, in both orders, in
//! every setting: apart, straddling the world's planes, inside the world's hull, touching.

use glam::{DVec3, Vec3};
use peel_compiler::compile::{compile_mesh, CompileOptions};
use peel_compiler::load::Mesh;
use peel_compiler::shade::{Shading, Surface};
use peel_compiler::tools::raster::HOST_PENDING;
use peel_compiler::tools::raster::{posed_header, render_posed_with, Settings};
use peel_compiler::tools::reference::{sampled, Grid};
use peel_compiler::tools::scenes::{self, boxed};
use peel_compiler::tools::shot::Shot;
use peel_e2e::{closed_sphere, polygons, reference};
use peel_runtime::error::ReadError;
use peel_runtime::place::{Object, Pose};
use peel_runtime::read::layout::{PARTS_HEADER_SIZE, PART_ENTRY_SIZE};
use peel_runtime::read::{Parts, Scene};
use peel_runtime::traverse::Order;

/// `mesh` compiled with ids, faceted, its ids starting at `first_id` (the triangles before
/// it in the frame's numbering).
fn compile(mesh: &Mesh, first_id: usize) -> Vec<u8> {
    let options = CompileOptions {
        ids: true,
        surface: Surface::Faceted,
        id_offset: first_id as u32,
        ..CompileOptions::default()
    };
    compile_mesh(mesh, &options, &|_| {}).expect("compile").1
}

/// The world: a floor and a few boxes, one of them hollow (a room of four walls).
fn world() -> Mesh {
    let mut t = Vec::new();
    let floor = [
        DVec3::new(-6.0, 0.0, -6.0),
        DVec3::new(-6.0, 0.0, 6.0),
        DVec3::new(6.0, 0.0, 6.0),
        DVec3::new(6.0, 0.0, -6.0),
    ];
    t.push([floor[0], floor[1], floor[2]]);
    t.push([floor[0], floor[2], floor[3]]);
    boxed(
        &mut t,
        DVec3::new(-4.0, 0.0, -4.0),
        DVec3::new(-2.5, 2.0, -2.5),
    );
    boxed(
        &mut t,
        DVec3::new(1.0, 0.0, -3.0),
        DVec3::new(2.0, 3.0, -1.0),
    );
    // A room's walls, thin boxes: an object can stand inside.
    boxed(
        &mut t,
        DVec3::new(-1.0, 0.0, 2.0),
        DVec3::new(3.0, 1.5, 2.2),
    );
    boxed(
        &mut t,
        DVec3::new(-1.0, 0.0, 5.0),
        DVec3::new(3.0, 1.5, 5.2),
    );
    boxed(
        &mut t,
        DVec3::new(-1.2, 0.0, 2.0),
        DVec3::new(-1.0, 1.5, 5.2),
    );
    scenes::mesh(t)
}

/// SplitMix64, for the poses.
struct Random(u64);

impl Random {
    fn next(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
    }
    fn range(&mut self, lo: f64, hi: f64) -> f32 {
        (lo + (hi - lo) * self.next()) as f32
    }
}

/// The triangles of `mesh` placed by `pose`, as the reference casts them.
fn posed(mesh: &Mesh, pose: &Pose) -> Vec<[DVec3; 3]> {
    let r = pose.rotation.as_dmat3();
    let t = pose.translation.as_dvec3();
    mesh.triangles
        .iter()
        .map(|tri| tri.vertices.map(|p| t + r * p))
        .collect()
}

/// Robust pixels whose id differs from the reference's, and robust pixels showing an object,
/// over `shots`, for the world and `objects` (meshes, compiled bytes, poses).
fn compare(
    world: (&Mesh, &[u8]),
    objects: &[(&Mesh, &[u8], Option<Pose>)],
    shots: &[Shot],
    settings: &Settings,
) -> (usize, usize) {
    let w = Scene::parse(world.1).unwrap();
    let parts: Vec<Object> = objects
        .iter()
        .map(|(_, bytes, pose)| Object::new(Scene::parse(bytes).unwrap(), *pose))
        .collect();
    let mut tris: Vec<[DVec3; 3]> = world.0.triangles.iter().map(|t| t.vertices).collect();
    let mut polys = polygons(world.1);
    let world_ids = tris.len() as u32;
    for (mesh, bytes, pose) in objects {
        match pose {
            Some(pose) => {
                tris.extend(posed(mesh, pose));
                let r = pose.rotation.as_dmat3();
                let t = pose.translation.as_dvec3();
                polys.extend(
                    polygons(bytes)
                        .into_iter()
                        .map(|p| p.into_iter().map(|q| t + r * q).collect::<Vec<_>>()),
                );
            }
            // Hidden: its ids stay numbered, on triangles nothing sees.
            None => tris.extend(mesh.triangles.iter().map(|_| [DVec3::splat(1e9); 3])),
        }
    }
    // Where two surfaces cross, their depths tie: the compiler cuts a static scene's
    // triangles there (its polygons' edges, above), the runtime cuts a posed object by the
    // world's planes. Those lines are edges too.
    let object_tris = &tris[world_ids as usize..];
    for (k, a) in object_tris.iter().enumerate() {
        for b in tris[..world_ids as usize]
            .iter()
            .chain(&object_tris[k + 1..])
        {
            if let Some(segment) = crossing(a, b) {
                polys.push(segment.to_vec());
            }
        }
    }
    let header = posed_header(Some(&w), &parts);
    let (mut bad, mut on_objects) = (0, 0);
    for shot in shots {
        let frame = render_posed_with(Some(&w), &parts, shot, settings)
            .unwrap_or_else(|e| panic!("{shot:?}: {e}"));
        let r = reference(&tris, &polys, shot, shot.near_over(&header));
        for k in (0..r.ids.len()).filter(|&k| r.robust[k]) {
            if frame.pixels[k] != r.ids[k] {
                eprintln!(
                    "{shot:?} pixel {k}: {} instead of {}",
                    frame.pixels[k], r.ids[k]
                );
                bad += 1;
            }
            if r.ids[k] > world_ids {
                on_objects += 1;
            }
        }
    }
    (bad, on_objects)
}

/// The segment along which triangles `a` and `b` cross, if they do.
fn crossing(a: &[DVec3; 3], b: &[DVec3; 3]) -> Option<[DVec3; 2]> {
    // The part of `t` on the plane of `u`, as a segment (or none).
    let on_plane = |t: &[DVec3; 3], u: &[DVec3; 3]| -> Option<[DVec3; 2]> {
        let n = (u[1] - u[0]).cross(u[2] - u[0]);
        let d = t.map(|p| n.dot(p - u[0]));
        let mut points = Vec::new();
        for i in 0..3 {
            let (p, q, dp, dq) = (t[i], t[(i + 1) % 3], d[i], d[(i + 1) % 3]);
            if dp == 0.0 {
                points.push(p);
            }
            if (dp < 0.0 && dq > 0.0) || (dp > 0.0 && dq < 0.0) {
                points.push(p + (q - p) * (dp / (dp - dq)));
            }
        }
        (points.len() >= 2).then(|| [points[0], points[1]])
    };
    let (s, t) = (on_plane(a, b)?, on_plane(b, a)?);
    let dir = s[1] - s[0];
    if dir.length_squared() == 0.0 {
        return None;
    }
    let at = |p: DVec3| dir.dot(p - s[0]) / dir.length_squared();
    let (t0, t1) = (at(t[0]).min(at(t[1])), at(t[0]).max(at(t[1])));
    let (lo, hi) = (t0.max(0.0), t1.min(1.0));
    (lo <= hi).then(|| [s[0] + dir * lo, s[0] + dir * hi])
}

fn orbit(centre: DVec3, radius: f64, height: f64) -> Vec<Shot> {
    (0..6)
        .map(|k| {
            let a = k as f64 * 1.047 + 0.2;
            let eye = centre + DVec3::new(a.cos() * radius, height, a.sin() * radius);
            Shot::new(eye, centre, 96, 72)
        })
        .collect()
}

/// Two objects over the world, at random poses: apart, straddling the boxes' and the
/// floor's planes, inside the room, sometimes hidden. No robust pixel differs from the
/// reference, front to back and back to front.
#[test]
fn posed_objects_match_the_reference() {
    let world_mesh = world();
    let torus = scenes::torus(16, 8);
    let sphere = closed_sphere(8, 12);
    let world_bytes = compile(&world_mesh, 0);
    let n = world_mesh.triangles.len();
    let torus_bytes = compile(&torus, n);
    let sphere_bytes = compile(&sphere, n + torus.triangles.len());
    let mut random = Random(7);
    let mut shown = 0;
    for round in 0..12 {
        let pose = |random: &mut Random| {
            Pose::from_degrees(
                Vec3::new(
                    random.range(-4.5, 4.5),
                    random.range(0.0, 2.5),
                    random.range(-4.5, 4.5),
                ),
                random.range(-180.0, 180.0),
                random.range(-90.0, 90.0),
                random.range(-180.0, 180.0),
            )
        };
        let a = pose(&mut random);
        let b = if round % 5 == 4 {
            None
        } else {
            Some(pose(&mut random))
        };
        let objects = [
            (&torus, &torus_bytes[..], Some(a)),
            (&sphere, &sphere_bytes[..], b),
        ];
        let shots = orbit(DVec3::new(0.0, 1.0, 0.0), 11.0, 5.0);
        // Both orders, and vertices projected in integers (as a core without an FPU does).
        let ways = [
            (Order::FrontToBack, false),
            (Order::BackToFront, false),
            (Order::FrontToBack, true),
        ];
        for (order, integer_vertices) in ways {
            let settings = Settings {
                order,
                ids: true,
                integer_vertices,
                ..Settings::default()
            };
            let result = std::panic::catch_unwind(|| {
                compare((&world_mesh, &world_bytes), &objects, &shots, &settings)
            });
            let (bad, on_objects) = match result {
                Ok(r) => r,
                Err(_) => panic!("round {round}: poses {a:?} {b:?}"),
            };
            assert_eq!(bad, 0, "round {round} {order:?}: poses {a:?} {b:?}");
            shown += on_objects;
        }
    }
    assert!(shown > 1000, "the objects showed on {shown} robust pixels");
}

/// Anti-aliased, flat colours: each pixel within half a unit of the exact mean of its 25
/// samples over the posed triangles, plus, per sample near an edge (the objects' cuts and
/// crossings count as edges), its share of the colours' range: the bound
/// `tests/antialias.rs` holds static scenes to.
#[test]
fn antialiased_posed_frames_match_the_exact_samples_but_near_edges() {
    let grid = Grid::RUNTIME;
    let k = f64::from(grid.samples());
    let flat = |mesh: &Mesh, first_id: usize| {
        let options = CompileOptions {
            shading: Shading::Flat,
            id_offset: first_id as u32,
            ..CompileOptions::default()
        };
        compile_mesh(mesh, &options, &|_| {}).expect("compile").1
    };
    let mut world_mesh = world();
    for (i, t) in world_mesh.triangles.iter_mut().enumerate() {
        t.colour = [40 + (i % 5) as u8 * 40, 200, 90];
    }
    let mut torus = scenes::torus(16, 8);
    for t in &mut torus.triangles {
        t.colour = [250, 60, 20];
    }
    let world_bytes = flat(&world_mesh, 0);
    let torus_bytes = flat(&torus, world_mesh.triangles.len());
    let world = Scene::parse(&world_bytes).unwrap();
    let background = [10, 10, 10];
    let mut random = Random(11);
    let (mut near_pixels, mut pixels) = (0, 0);
    for _ in 0..4 {
        let pose = Pose::from_degrees(
            Vec3::new(
                random.range(-4.0, 4.0),
                random.range(0.0, 2.0),
                random.range(-4.0, 4.0),
            ),
            random.range(-180.0, 180.0),
            random.range(-90.0, 90.0),
            0.0,
        );
        let objects = [Object::new(Scene::parse(&torus_bytes).unwrap(), Some(pose))];
        let mut tris: Vec<[DVec3; 3]> = world_mesh.triangles.iter().map(|t| t.vertices).collect();
        let mut colours: Vec<[u8; 3]> = world_mesh.triangles.iter().map(|t| t.colour).collect();
        let mut polys = polygons(&world_bytes);
        let placed = posed(&torus, &pose);
        let (r, t) = (pose.rotation.as_dmat3(), pose.translation.as_dvec3());
        polys.extend(
            polygons(&torus_bytes)
                .into_iter()
                .map(|p| p.into_iter().map(|q| t + r * q).collect::<Vec<_>>()),
        );
        for a in &placed {
            for b in &tris {
                if let Some(segment) = crossing(a, b) {
                    polys.push(segment.to_vec());
                }
            }
        }
        tris.extend(placed);
        colours.extend(torus.triangles.iter().map(|t| t.colour));
        let (lo, hi) =
            colours
                .iter()
                .chain([&background])
                .fold(([255u8; 3], [0u8; 3]), |(lo, hi), c| {
                    (
                        [0, 1, 2].map(|i| lo[i].min(c[i])),
                        [0, 1, 2].map(|i| hi[i].max(c[i])),
                    )
                });
        let header = posed_header(Some(&world), &objects);
        for shot in orbit(DVec3::new(0.0, 1.0, 0.0), 11.0, 5.0).iter().take(3) {
            let near = shot.near_over(&header);
            let exact = sampled(
                &tris,
                &polys,
                shot,
                near,
                grid,
                |id, _| colours[id],
                background,
            );
            let settings = Settings {
                antialias: Some(HOST_PENDING),
                background,
                ..Settings::default()
            };
            let aa = render_posed_with(Some(&world), &objects, shot, &settings).unwrap();
            assert!(aa.stats.antialiased);
            let rgb = aa.to_rgb();
            for (p, (want, &m)) in exact.colours.iter().zip(&exact.near_edge).enumerate() {
                pixels += 1;
                near_pixels += usize::from(m > 0);
                for c in 0..3 {
                    let error = (f64::from(rgb[3 * p + c]) - want[c]).abs();
                    let bound = 0.5 + f64::from(m) * f64::from(hi[c] - lo[c]) / k;
                    assert!(
                        error <= bound + 1e-9,
                        "pose {pose:?}, {shot:?}: pixel {p} channel {c} off by {error:.3} > {bound:.3}"
                    );
                }
            }
        }
    }
    assert!(near_pixels > 0 && near_pixels < pixels);
}

/// A file of parts as the compiler writes it, read by the runtime: the world, the objects by
/// name and index, and a corrupt name or table refused with the byte offset of its entry.
#[test]
fn files_of_parts_read_back() {
    let world_mesh = world();
    let world_bytes = compile(&world_mesh, 0);
    let torus_bytes = compile(&scenes::torus(8, 6), world_mesh.triangles.len());
    let objects = vec![("wheel".to_string(), torus_bytes.clone())];
    let file = peel_compiler::write::parts::parts_file(Some(&world_bytes), &objects).unwrap();
    let parts = Parts::parse(&file).unwrap();
    assert!(parts.has_table());
    assert_eq!(parts.object_count(), 1);
    let world = parts.world().expect("a world");
    assert_eq!(world.header(), Scene::parse(&world_bytes).unwrap().header());
    let (name, wheel) = parts.object(0).expect("an object");
    assert_eq!(name, "wheel");
    assert_eq!(wheel.header(), Scene::parse(&torus_bytes).unwrap().header());
    assert_eq!(parts.find("wheel").map(|(k, _)| k), Some(0));
    assert!(parts.find("world").is_none() && parts.object(1).is_none());
    // A plain tree file reads as a world alone.
    let plain = Parts::parse(&world_bytes).unwrap();
    assert!(!plain.has_table() && plain.object_count() == 0 && plain.world().is_some());
    // The object's name made empty: its table entry (the second) is named.
    let entry = PARTS_HEADER_SIZE + PART_ENTRY_SIZE;
    let mut bad = file.clone();
    bad[entry + 12..entry + 16].copy_from_slice(&0u32.to_le_bytes());
    assert_eq!(
        Parts::parse(&bad).unwrap_err(),
        ReadError::BadName { offset: entry }
    );
    // A tree cut short is refused at a byte offset inside it.
    let mut short = file.clone();
    let len = u32::from_le_bytes(short[entry + 4..entry + 8].try_into().unwrap());
    short[entry + 4..entry + 8].copy_from_slice(&(len - 8).to_le_bytes());
    let start = u32::from_le_bytes(short[entry..entry + 4].try_into().unwrap()) as usize;
    match Parts::parse(&short).unwrap_err() {
        ReadError::Truncated { offset } | ReadError::CountMismatch { offset } => {
            assert!(offset >= start, "{offset} before the tree at {start}")
        }
        e => panic!("{e}"),
    }
}

/// Two boxes whose faces touch (their boxes share a plane, which orders them), on the floor
/// inside the room, turned together about the vertical: drawn, and no robust pixel differs
/// from the reference.
#[test]
fn touching_objects_are_ordered_by_their_common_plane() {
    let world_mesh = world();
    let mut cube = Vec::new();
    boxed(&mut cube, DVec3::splat(-0.5), DVec3::splat(0.5));
    let cube = scenes::mesh(cube);
    let world_bytes = compile(&world_mesh, 0);
    let n = world_mesh.triangles.len();
    let a_bytes = compile(&cube, n);
    let b_bytes = compile(&cube, n + 12);
    let mut shown = 0;
    for turn in [0.0f32, 30.0, 75.0] {
        let r = glam::Mat3::from_rotation_y(turn.to_radians());
        let centre = Vec3::new(1.0, 0.5, 3.6);
        let a = Pose::from_degrees(centre + r * Vec3::new(-0.5, 0.0, 0.0), turn, 0.0, 0.0);
        let b = Pose::from_degrees(centre + r * Vec3::new(0.5, 0.0, 0.0), turn, 0.0, 0.0);
        let objects = [
            (&cube, &a_bytes[..], Some(a)),
            (&cube, &b_bytes[..], Some(b)),
        ];
        let shots = orbit(DVec3::new(1.0, 0.5, 3.6), 6.0, 4.0);
        for order in [Order::FrontToBack, Order::BackToFront] {
            let settings = Settings {
                order,
                ids: true,
                ..Settings::default()
            };
            let (bad, on_objects) =
                compare((&world_mesh, &world_bytes), &objects, &shots, &settings);
            assert_eq!(bad, 0, "turned {turn} {order:?}");
            shown += on_objects;
        }
    }
    assert!(shown > 1000, "the boxes showed on {shown} robust pixels");
}

/// The memory the sizes file gives a file of parts draws the firmware guide's scene: the
/// demo's world with its torus turning on the ground, around an orbit, front to back.
#[test]
fn the_sizes_files_object_memory_draws_the_turning_torus() {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    let dir = std::env::temp_dir().join(format!("peel-objects-sizes-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let out = peel_compiler::Builder::new(root.join("fixtures/demo.obj"))
        .object("torus", root.join("fixtures/demo-torus.obj"))
        .out_dir(&dir)
        .cache(false)
        .compile()
        .expect("compile");
    let sizes = std::fs::read_to_string(&out.sizes).unwrap();
    let constant = |name: &str| -> usize {
        let prefix = format!("pub const {name}: usize = ");
        sizes
            .lines()
            .find_map(|l| l.strip_prefix(&prefix)?.strip_suffix(';'))
            .unwrap_or_else(|| panic!("no {name}"))
            .parse()
            .unwrap()
    };
    let bytes = std::fs::read(&out.peel).unwrap();
    let _ = std::fs::remove_dir_all(&dir);
    let parts = Parts::parse(&bytes).unwrap();
    let (world, (_, torus)) = (parts.world().unwrap(), parts.object(0).unwrap());
    assert_eq!(constant("OBJECTS"), 1);
    // The memory as the sizes file sizes it (the host's types are larger; the counts are
    // what matters).
    let (steps, verts) = (constant("OBJECT_STEPS"), constant("VERTS"));
    let centre = Vec3::new(-2.1, 0.34, 1.7);
    let mut most_steps = 0;
    for k in 0..24 {
        let turn = Pose::from_degrees(Vec3::ZERO, k as f32 * 15.0, 0.0, 0.0);
        let pose = Pose {
            translation: centre - turn.rotation * centre,
            ..turn
        };
        let objects = [Object::new(torus, Some(pose))];
        let header = posed_header(Some(&world), &objects);
        let eye = peel_runtime::camera::Orbit {
            azimuth_deg: k as f64 * 15.0,
            ..Default::default()
        }
        .pose(&header);
        let shot = Shot::new(eye.eye, eye.target, 320, 240);
        let frame = render_posed_with(Some(&world), &objects, &shot, &Settings::default())
            .expect("a frame");
        most_steps = most_steps.max(frame.stats.object_steps as usize);
        // The largest polygon (12) and the clip planes (5), two vertices a cutting plane.
        assert!(12 + 5 + 2 * frame.stats.object_planes as usize <= verts);
    }
    eprintln!("the turning torus: at most {most_steps} steps of the {steps} the sizes file gives");
    assert!(
        most_steps > 1 && most_steps <= steps,
        "{most_steps} steps, {steps} given"
    );
}
