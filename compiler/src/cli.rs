//! The `peel` subcommands other than `compile`: inspect, dump, render, demo and bench.

use std::path::{Path, PathBuf};

use clap::Args;
use glam::DVec3;

use glam::Vec3;
use peel_compiler::compile::CompileOptions;
use peel_compiler::shade::normals::Crease;
use peel_compiler::shade::Surface;
use peel_compiler::tools::raster::{
    png, posed_header, render_bytes_with, render_posed_named, Frame, Settings, EMPTY_SCENE,
    HOST_PENDING,
};
use peel_compiler::tools::shot::Shot;
use peel_compiler::FrameMemory;
use peel_runtime::camera::Orbit;
use peel_runtime::place::{Object, Pose};
use peel_runtime::read::{Header, Parts};
use peel_runtime::traverse::Order;

/// Parse `x,y,z` (negative numbers allowed: `--eye=-1,2,3` or `--eye -1,2,3`).
pub fn parse_dvec3(s: &str) -> Result<DVec3, String> {
    let parts: Vec<&str> = s.split(',').map(str::trim).collect();
    if parts.len() != 3 {
        return Err(format!("expected x,y,z, got '{s}'"));
    }
    let mut v = [0.0f64; 3];
    for (slot, p) in v.iter_mut().zip(&parts) {
        let x: f64 = p
            .parse()
            .map_err(|_| format!("'{p}' is not a number (in '{s}')"))?;
        if !x.is_finite() {
            return Err(format!("'{p}' is not finite (in '{s}')"));
        }
        *slot = x;
    }
    Ok(DVec3::from_array(v))
}

/// Parse `--object NAME=FILE`: a name of 1 to `MAX_NAME` bytes, then the OBJ file.
pub fn parse_object(s: &str) -> Result<(String, PathBuf), String> {
    use peel_runtime::read::layout::MAX_NAME;
    let (name, file) = s
        .split_once('=')
        .ok_or_else(|| format!("expected NAME=FILE, got '{s}' (no '=')"))?;
    if name.is_empty() {
        return Err(format!("'{s}' has no name before '='"));
    }
    if name.len() > MAX_NAME as usize {
        return Err(format!(
            "the name '{name}' has {} bytes: at most {MAX_NAME}",
            name.len()
        ));
    }
    if file.is_empty() {
        return Err(format!("'{s}' has no file after '='"));
    }
    Ok((name.to_string(), PathBuf::from(file)))
}

/// `--pose` values: `NAME=tx,ty,tz` or `NAME=tx,ty,tz,yaw,pitch,roll`, the angles in degrees (see
/// [`Pose::from_degrees`]).
pub fn parse_pose(s: &str) -> Result<(String, Pose), String> {
    let (name, values) = s
        .split_once('=')
        .ok_or_else(|| format!("expected NAME=tx,ty,tz[,yaw,pitch,roll], got '{s}' (no '=')"))?;
    if name.is_empty() {
        return Err(format!("'{s}' has no name before '='"));
    }
    let numbers: Vec<f32> = values
        .split(',')
        .map(|v| {
            let x: f32 = v
                .trim()
                .parse()
                .map_err(|_| format!("'{v}' in '{s}' is not a number"))?;
            if x.is_finite() {
                Ok(x)
            } else {
                Err(format!("'{v}' in '{s}' is not finite"))
            }
        })
        .collect::<Result<_, _>>()?;
    let angles = match numbers.len() {
        3 => [0.0; 3],
        6 => [numbers[3], numbers[4], numbers[5]],
        n => {
            return Err(format!(
                "'{s}' gives {n} numbers: give tx,ty,tz or tx,ty,tz,yaw,pitch,roll"
            ))
        }
    };
    let t = Vec3::new(numbers[0], numbers[1], numbers[2]);
    Ok((
        name.to_string(),
        Pose::from_degrees(t, angles[0], angles[1], angles[2]),
    ))
}

/// Parse a direction `x,y,z`: finite, and of some length (`--up`, `--light`).
pub fn parse_direction(s: &str) -> Result<DVec3, String> {
    let v = parse_dvec3(s)?;
    if v.try_normalize().is_none() {
        return Err(format!(
            "the direction '{s}' has no length: give x,y,z not all zero"
        ));
    }
    Ok(v)
}

/// Parse a vertical field of view in degrees: strictly between 0 and 180.
pub fn parse_fov(s: &str) -> Result<f64, String> {
    let fov = parse_finite(s)?;
    if !(fov > 0.0 && fov < 180.0) {
        return Err(format!(
            "the field of view must be strictly between 0 and 180 degrees, got {fov}"
        ));
    }
    Ok(fov)
}

/// Parse a positive finite number (`--near`, `--distance`).
pub fn parse_positive(s: &str) -> Result<f64, String> {
    let x = parse_finite(s)?;
    if x <= 0.0 {
        return Err(format!("must be a positive number, got {x}"));
    }
    Ok(x)
}

fn parse_finite(s: &str) -> Result<f64, String> {
    s.trim()
        .parse::<f64>()
        .ok()
        .filter(|x| x.is_finite())
        .ok_or_else(|| format!("'{s}' is not a finite number"))
}

/// Parse the largest side of a texture (`--max-texture`): a power of two from 1 to 1024.
pub fn parse_max_texture(s: &str) -> Result<u32, String> {
    let options = peel_compiler::load::LoadOptions {
        max_texture: s
            .trim()
            .parse()
            .map_err(|_| format!("'{s}' is not a whole number of texels"))?,
        ..peel_compiler::load::LoadOptions::default()
    };
    options.check().map_err(|_| {
        format!(
            "the largest texture side must be a power of two from 1 to {}, got {s}",
            1u32 << peel_runtime::read::layout::MAX_TEXTURE_LOG2
        )
    })?;
    Ok(options.max_texture)
}

/// Parse a crease angle in degrees, from 0 to 180 (`--crease`).
pub fn parse_crease(s: &str) -> Result<peel_compiler::shade::normals::Crease, String> {
    let degrees = s
        .trim()
        .parse::<f64>()
        .map_err(|_| format!("'{s}' is not a number of degrees"))?;
    peel_compiler::shade::normals::Crease::new(degrees)
        .map_err(|_| format!("the crease angle must be from 0 to 180 degrees, got {s}"))
}

/// The image size `peel render` draws without `--size`.
pub const DEFAULT_RENDER_SIZE: &str = "640x480";

/// Parse `WxH`.
pub fn parse_size(s: &str) -> Result<(u32, u32), String> {
    let (w, h) = s
        .split_once(['x', 'X'])
        .ok_or_else(|| format!("expected WxH, got '{s}'"))?;
    let w: u32 = w
        .trim()
        .parse()
        .map_err(|_| format!("bad width in '{s}'"))?;
    let h: u32 = h
        .trim()
        .parse()
        .map_err(|_| format!("bad height in '{s}'"))?;
    if w == 0 || h == 0 || w > 16384 || h > 16384 {
        return Err(format!(
            "image size '{s}' must be between 1x1 and 16384x16384"
        ));
    }
    Ok((w, h))
}

/// Parse `r,g,b` with 0..=255 channels.
pub fn parse_rgb(s: &str) -> Result<[u8; 3], String> {
    let parts: Vec<&str> = s.split(',').map(str::trim).collect();
    let mut c = [0u8; 3];
    if parts.len() != 3 {
        return Err(format!("expected r,g,b, got '{s}'"));
    }
    for (slot, p) in c.iter_mut().zip(&parts) {
        *slot = p
            .parse()
            .map_err(|_| format!("'{p}' is not a channel value 0..=255 (in '{s}')"))?;
    }
    Ok(c)
}

/// Arguments of `peel render`.
#[derive(Args)]
pub struct RenderArgs {
    /// The .peel file.
    pub file: PathBuf,
    /// Eye position x,y,z (with --target; without both, the scene is framed by --orbit).
    #[arg(long, value_parser = parse_dvec3, allow_hyphen_values = true, requires = "target", value_name = "X,Y,Z")]
    pub eye: Option<DVec3>,
    /// Point looked at x,y,z (with --eye).
    #[arg(long, value_parser = parse_dvec3, allow_hyphen_values = true, requires = "eye", value_name = "X,Y,Z")]
    pub target: Option<DVec3>,
    /// Without --eye/--target: look at the centre of the scene's bounding box from these
    /// angles in degrees, azimuth around the y axis (from +z towards +x) and elevation.
    #[arg(long, value_parser = parse_orbit, allow_hyphen_values = true, conflicts_with = "eye", value_name = "AZ,EL")]
    pub orbit: Option<(f64, f64)>,
    /// Without --eye/--target: the eye's distance from the box centre in bounding radii, a
    /// positive number (default: the nearest at which the whole scene is in view).
    #[arg(long, value_parser = parse_positive, allow_hyphen_values = true, conflicts_with = "eye", value_name = "K")]
    pub distance: Option<f64>,
    /// Up direction x,y,z (not all zero).
    #[arg(long, value_parser = parse_direction, allow_hyphen_values = true, default_value = "0,1,0", value_name = "X,Y,Z")]
    pub up: DVec3,
    /// Vertical field of view in degrees, strictly between 0 and 180.
    #[arg(long, value_parser = parse_fov, allow_hyphen_values = true, default_value = "60", value_name = "DEG")]
    pub fov: f64,
    /// Image size WxH, from 1x1 to 16384x16384.
    #[arg(long, value_parser = parse_size, default_value = DEFAULT_RENDER_SIZE, value_name = "WxH")]
    pub size: (u32, u32),
    /// Near distance, a positive number (default: 1e-3 x the scene's bounding-box diagonal).
    #[arg(long, value_parser = parse_positive, allow_hyphen_values = true, value_name = "D")]
    pub near: Option<f64>,
    /// Write the id image (source triangle id + 1 as 24-bit RGB; needs a file compiled with --ids).
    #[arg(long)]
    pub ids: bool,
    /// Background colour R,G,B (0-255 each).
    #[arg(long, value_parser = parse_rgb, default_value = "0,0,0", value_name = "R,G,B")]
    pub background: [u8; 3],
    /// Drawing order: front-to-back writes each pixel once; back-to-front is the plain
    /// painter's algorithm.
    #[arg(long, value_enum, default_value_t = OrderArg::FrontToBack)]
    pub order: OrderArg,
    /// Draw everything: no frustum or coverage culling (changes no pixel; for measuring).
    #[arg(long)]
    pub no_cull: bool,
    /// Project vertices in integers, as firmware for a core without an FPU does
    /// (`Renderer::integer_vertices`: a subpixel unit off now and then, so edge pixels can differ).
    #[arg(long)]
    pub integer_vertices: bool,
    /// Anti-aliased: each pixel the average of 5 x 5 samples, edges blended with the
    /// background (`Renderer::antialias`).
    #[arg(long)]
    pub antialias: bool,
    /// Textures filtered bilinearly: each pixel the four texels around its centre, weighted
    /// (`Renderer::bilinear`); by default the texel it falls in.
    #[arg(long)]
    pub bilinear: bool,
    /// Place an object of a file of parts: NAME=tx,ty,tz or NAME=tx,ty,tz,yaw,pitch,roll,
    /// angles in degrees, so that its point p goes to T + Ry(yaw) Rx(pitch) Rz(roll) p
    /// (repeatable; an object without one stays where its file puts it).
    #[arg(long = "pose", value_parser = parse_pose, allow_hyphen_values = true, value_name = "NAME=T[,ANGLES]")]
    pub poses: Vec<(String, Pose)>,
    /// Hide an object of a file of parts (repeatable).
    #[arg(long = "hide", value_name = "NAME")]
    pub hidden: Vec<String>,
    /// Print the frame's statistics (polygons visited, culled, drawn, pixels written, overdraw).
    #[arg(long)]
    pub stats: bool,
    /// Output PNG (the name must end in .png).
    #[arg(short, long, value_name = "FILE")]
    pub output: PathBuf,
}

/// `--orbit` values: `azimuth,elevation` in degrees, the elevation strictly between -90 and 90.
pub fn parse_orbit(s: &str) -> Result<(f64, f64), String> {
    let parts: Vec<&str> = s.split(',').map(str::trim).collect();
    let [az, el] = parts[..] else {
        return Err(format!("expected azimuth,elevation in degrees, got '{s}'"));
    };
    let number = |p: &str| {
        p.parse::<f64>()
            .ok()
            .filter(|v| v.is_finite())
            .ok_or_else(|| format!("'{p}' is not a finite number (in '{s}')"))
    };
    let (az, el) = (number(az)?, number(el)?);
    if !(el > -90.0 && el < 90.0) {
        return Err(format!(
            "elevation {el} is not strictly between -90 and 90 (straight up or down, the view \
             would be parallel to the up direction)"
        ));
    }
    Ok((az, el))
}

/// The camera `args` ask for over the scene with header `header`: `--eye`/`--target`, or an
/// orbit that frames the scene.
fn render_shot(args: &RenderArgs, header: &Header) -> Result<Shot, String> {
    let (eye, target) = match (args.eye, args.target) {
        (Some(eye), Some(target)) => (eye, target),
        _ => {
            let (azimuth_deg, elevation_deg) = args.orbit.unwrap_or_else(|| {
                let o = Orbit::default();
                (o.azimuth_deg, o.elevation_deg)
            });
            let distance = args
                .distance
                .unwrap_or_else(|| Orbit::fitting_distance(args.fov, args.size.0, args.size.1));
            let pose = Orbit {
                azimuth_deg,
                elevation_deg,
                distance,
            }
            .pose(header);
            (pose.eye, pose.target)
        }
    };
    Ok(Shot {
        eye,
        target,
        up: args.up,
        fov_y_deg: args.fov,
        width: args.size.0,
        height: args.size.1,
        near: args.near,
    })
}

/// The flag that fixes a degenerate camera, when one does (the values are checked as they are
/// parsed; these two come from their combination).
fn camera_hint(shot: &Shot) -> Option<&'static str> {
    let forward = shot.target - shot.eye;
    if forward.length_squared() == 0.0 {
        return Some("give --eye and --target different points");
    }
    let cross = forward.normalize().cross(shot.up.normalize_or_zero());
    (cross.length() < 1e-9)
        .then_some("looking straight up or down? pass another --up, e.g. --up=0,0,-1")
}

/// `--order` values.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum OrderArg {
    /// Reverse painter order with a span buffer: every pixel written once.
    FrontToBack,
    /// Painter's order: far polygons first, overdraw.
    BackToFront,
}

fn read(path: &Path) -> Result<Vec<u8>, String> {
    std::fs::read(path).map_err(|e| format!("{}: cannot read: {e}", path.display()))
}

/// `peel inspect`: the counters, and the frame memory measured at `size` if given.
pub fn inspect(path: &Path, json: bool, size: Option<(u32, u32)>) -> Result<(), String> {
    let bytes = read(path)?;
    if peel_compiler::write::parts::is_parts_file(&bytes) {
        let info = peel_compiler::dump::inspect_parts(&bytes, size)
            .map_err(|e| format!("{}: invalid file of parts: {e}", path.display()))?;
        if json {
            println!(
                "{}",
                serde_json::to_string_pretty(&info).map_err(|e| e.to_string())?
            );
        } else {
            print!("{}", peel_compiler::dump::inspect_parts_text(&info));
        }
        return Ok(());
    }
    let mut info = peel_compiler::dump::inspect(&bytes)
        .map_err(|e| format!("{}: invalid .peel file: {e}", path.display()))?;
    if let Some((width, height)) = size {
        info.frame_memory = FrameMemory::measured(&bytes, width, height)
            .map_err(|e| format!("{}: {e}", path.display()))?;
    }
    if json {
        println!(
            "{}",
            serde_json::to_string_pretty(&info).map_err(|e| e.to_string())?
        );
    } else {
        print!("{}", peel_compiler::dump::inspect_text(&info));
    }
    Ok(())
}

/// `peel dump`.
pub fn dump(path: &Path) -> Result<(), String> {
    let bytes = read(path)?;
    if peel_compiler::write::parts::is_parts_file(&bytes) {
        let parts = peel_compiler::write::parts::read_parts(&bytes)
            .map_err(|e| format!("{}: invalid file of parts: {e}", path.display()))?;
        let names: Vec<&str> = (parts.iter())
            .map(|p| if p.name.is_empty() { "(world)" } else { p.name })
            .collect();
        return Err(format!(
            "{}: a file of parts ({}): peel dump reads a single tree; peel inspect shows each \
             part",
            path.display(),
            names.join(", ")
        ));
    }
    let yaml = peel_compiler::dump::dump_yaml(&bytes)
        .map_err(|e| format!("{}: invalid .peel file: {e}", path.display()))?;
    // A reader that stops early (`peel dump f | head`) is not an error.
    match std::io::Write::write_all(&mut std::io::stdout().lock(), yaml.as_bytes()) {
        Err(e) if e.kind() != std::io::ErrorKind::BrokenPipe => Err(format!("stdout: {e}")),
        _ => Ok(()),
    }
}

/// `peel render`.
pub fn render(args: &RenderArgs) -> Result<(), String> {
    let png_name = args
        .output
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("png"));
    if !png_name {
        return Err(format!(
            "{}: peel render writes PNG only: give the output a .png name",
            args.output.display()
        ));
    }
    let bytes = read(&args.file)?;
    let parts = Parts::parse(&bytes)
        .map_err(|e| format!("{}: invalid .peel file: {e}", args.file.display()))?;
    let world = parts.world();
    let mut objects = Vec::new();
    let mut names = Vec::new();
    for k in 0..parts.object_count() {
        if let Some((name, scene)) = parts.object(k) {
            objects.push(Object::new(scene, Some(Pose::IDENTITY)));
            names.push(name);
        }
    }
    let unknown = |name: &str, option: &str| {
        let known = if names.is_empty() {
            "it has no objects".to_string()
        } else {
            format!("its objects are {}", names.join(", "))
        };
        format!(
            "{}: {option} {name}: no such object ({known})",
            args.file.display()
        )
    };
    for (name, pose) in &args.poses {
        let k = names
            .iter()
            .position(|n| n == name)
            .ok_or_else(|| unknown(name, "--pose"))?;
        objects[k].pose = Some(*pose);
    }
    for name in &args.hidden {
        let k = names
            .iter()
            .position(|n| n == name)
            .ok_or_else(|| unknown(name, "--hide"))?;
        objects[k].pose = None;
    }
    let parts_drawn = || {
        world.iter().chain(
            objects
                .iter()
                .filter(|o| o.pose.is_some())
                .map(|o| &o.scene),
        )
    };
    if parts_drawn().all(|s| s.header().polygon_count == 0) {
        return Err(format!("{}: {EMPTY_SCENE}", args.file.display()));
    }
    let header = match (&world, objects.is_empty()) {
        (Some(scene), true) => scene.header(),
        _ => posed_header(world.as_ref(), &objects),
    };
    let shot = render_shot(args, &header)?;
    let settings = Settings {
        order: match args.order {
            OrderArg::FrontToBack => Order::FrontToBack,
            OrderArg::BackToFront => Order::BackToFront,
        },
        cull: !args.no_cull,
        ids: args.ids,
        background: args.background,
        integer_vertices: args.integer_vertices,
        antialias: args
            .antialias
            .then_some(peel_compiler::tools::raster::HOST_PENDING),
        bilinear: args.bilinear,
    };
    let frame = if parts.has_table() {
        render_posed_named(world.as_ref(), &objects, &names, &shot, &settings)
    } else {
        render_bytes_with(&bytes, &shot, &settings)
    };
    let frame = frame.map_err(|e| match camera_hint(&shot) {
        Some(hint) => format!("{}: {e}: {hint}", args.file.display()),
        None => format!("{}: {e}", args.file.display()),
    })?;
    write_png(&args.output, &frame)?;
    if frame.stats.pixels_written == 0 {
        eprintln!(
            "warning: {}: no pixel of the scene is in view (the image is all background); \
             without --eye/--target the scene is framed for you",
            args.output.display()
        );
    }
    if args.stats {
        let s = &frame.stats;
        println!("polygons visited: {}", s.polygons_visited);
        println!("subtrees culled (frustum): {}", s.nodes_culled_frustum);
        println!("subtrees culled (covered): {}", s.nodes_culled_covered);
        println!("polygons culled (covered): {}", s.polygons_culled_covered);
        println!("polygons drawn: {}", s.polygons_drawn);
        println!("pixels written: {}", s.pixels_written);
        match s.distinct_pixels {
            Some(d) => println!("distinct pixels: {d}"),
            None => println!("distinct pixels: unknown"),
        }
        match s.overdraw() {
            Some(o) => println!("overdraw: {o:.2}"),
            None => println!("overdraw: unknown"),
        }
        println!("stopped when full: {}", s.stopped_full);
        println!("span memory fallback: {}", s.fallback);
        if parts.has_table() {
            println!("object steps: {}", s.object_steps);
            println!("object planes: {}", s.object_planes);
        }
    }
    println!(
        "{} -> {}: {}x{}, {} polygons visited, {} drawn, {} pixels written",
        args.file.display(),
        args.output.display(),
        frame.width,
        frame.height,
        frame.stats.polygons_visited,
        frame.stats.polygons_drawn,
        frame.stats.pixels_written
    );
    Ok(())
}

fn write_png(path: &Path, frame: &Frame) -> Result<(), String> {
    let png = png(frame)?;
    peel_compiler::write::write_atomic(path, &png).map_err(|e| e.to_string())
}

/// The demo's camera: above and in front of the scene, looking at its middle.
pub const DEMO_SHOT: Shot = Shot {
    fov_y_deg: 50.0,
    ..Shot::new(
        DVec3::new(5.5, 4.5, 7.5),
        DVec3::new(0.0, 0.8, 0.0),
        800,
        600,
    )
};

/// `peel demo`: write the built-in scene, compile it, render it: smooth shading, the default
/// sun's shadows, anti-aliased.
pub fn demo(out: &Path) -> Result<(), String> {
    std::fs::create_dir_all(out).map_err(|e| format!("{}: cannot create: {e}", out.display()))?;
    let obj = out.join("demo.obj");
    std::fs::write(&obj, format!("{DEMO_OBJ}\n{DEMO_TORUS_OBJ}"))
        .map_err(|e| format!("{}: {e}", obj.display()))?;
    for (name, text) in [("demo.mtl", DEMO_MTL), ("demo-torus.mtl", DEMO_TORUS_MTL)] {
        let mtl = out.join(name);
        std::fs::write(&mtl, text).map_err(|e| format!("{}: {e}", mtl.display()))?;
    }
    let peel = out.join("demo.peel");
    let mut options = CompileOptions {
        surface: Surface::Smooth(Crease::default()),
        ..CompileOptions::default()
    };
    options.build.shadows = options.shading.light();
    let bytes = crate::compile_to(&obj, &peel, &options, None)?;
    let settings = Settings {
        background: [24, 26, 32],
        antialias: Some(HOST_PENDING),
        ..Settings::default()
    };
    let frame = render_bytes_with(&bytes, &DEMO_SHOT, &settings)?;
    let png_path = out.join("demo.png");
    write_png(&png_path, &frame)?;
    say(&png_path, &frame);
    demo_objects(out, &options, &settings)?;
    demo_textured(out, &settings)?;
    demo_transparent(out)
}

/// The demo's transparent scenes, unlit so that each colour is its material's: the panes that
/// cross one another and the boxes that interpenetrate, each drawn by Peel front to back
/// (`demo-panes.png`, `demo-boxes.png`) and by a z-buffer that sorts the transparent
/// triangles by their centroid's depth (`demo-panes-sorted.png`, `demo-boxes-sorted.png`).
fn demo_transparent(out: &Path) -> Result<(), String> {
    use peel_compiler::tools::scenes;
    let options = CompileOptions {
        shading: peel_compiler::shade::Shading::Flat,
        surface: Surface::Faceted,
        ..CompileOptions::default()
    };
    let background = [24, 26, 32];
    for (name, scene) in [
        ("panes", scenes::crossing_panes()),
        ("boxes", scenes::interpenetrating_boxes()),
    ] {
        let mtl = format!("demo-{name}.mtl");
        let mtl_path = out.join(&mtl);
        std::fs::write(&mtl_path, scene.mtl())
            .map_err(|e| format!("{}: {e}", mtl_path.display()))?;
        let obj = out.join(format!("demo-{name}.obj"));
        std::fs::write(&obj, scene.obj(&mtl)).map_err(|e| format!("{}: {e}", obj.display()))?;
        let peel = out.join(format!("demo-{name}.peel"));
        let bytes = crate::compile_to(&obj, &peel, &options, None)?;
        let first = scene.shots.first().ok_or("a scene without views")?;
        let shot = Shot {
            width: 640,
            height: 480,
            ..*first
        };
        let settings = Settings {
            background,
            ..Settings::default()
        };
        let frame = render_bytes_with(&bytes, &shot, &settings)?;
        let png_path = out.join(format!("demo-{name}.png"));
        write_png(&png_path, &frame)?;
        say(&png_path, &frame);
        let header = peel_runtime::read::Scene::parse(&bytes)
            .map_err(|e| e.to_string())?
            .header();
        let colours = scene.colours();
        let sorted = peel_compiler::tools::bench_frames::sorted_picture(
            &scene.corners(),
            |id, _| colours[id].map(f64::from),
            &scene.opacities(),
            background,
            &shot,
            shot.near_over(&header),
        )?;
        let frame = Frame {
            pixels: (sorted.iter())
                .map(|p| u32::from_be_bytes([0, p[0], p[1], p[2]]))
                .collect(),
            ..frame
        };
        let png_path = out.join(format!("demo-{name}-sorted.png"));
        write_png(&png_path, &frame)?;
        println!(
            "{}: the same, by a z-buffer sorting by depth",
            png_path.display()
        );
    }
    Ok(())
}

/// The demo's textured scenes: the die standing on the tiled floor, lit, with the sun's
/// shadows (which cut the floor where they fall: its pieces keep the tile's coordinates),
/// written with its pictures (`demo-textured.png`); and a generated torus under a
/// checkerboard, smoothly shaded (`demo-checker.png`).
fn demo_textured(out: &Path, settings: &Settings) -> Result<(), String> {
    let files: [(&str, &[u8]); 9] = [
        ("demo-textured.obj", DEMO_TEXTURED_OBJ.as_bytes()),
        ("demo-textured.mtl", DEMO_TEXTURED_MTL.as_bytes()),
        (
            "textured-box/face1.png",
            include_bytes!("../../fixtures/textured-box/face1.png"),
        ),
        (
            "textured-box/face2.png",
            include_bytes!("../../fixtures/textured-box/face2.png"),
        ),
        (
            "textured-box/face3.png",
            include_bytes!("../../fixtures/textured-box/face3.png"),
        ),
        (
            "textured-box/face4.png",
            include_bytes!("../../fixtures/textured-box/face4.png"),
        ),
        (
            "textured-box/face5.png",
            include_bytes!("../../fixtures/textured-box/face5.png"),
        ),
        (
            "textured-box/face6.png",
            include_bytes!("../../fixtures/textured-box/face6.png"),
        ),
        (
            "textured-floor/tile.png",
            include_bytes!("../../fixtures/textured-floor/tile.png"),
        ),
    ];
    for (name, bytes) in files {
        let path = out.join(name);
        if let Some(dir) = path.parent() {
            std::fs::create_dir_all(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
        }
        std::fs::write(&path, bytes).map_err(|e| format!("{}: {e}", path.display()))?;
    }
    let mut options = CompileOptions::default();
    options.build.shadows = options.shading.light();
    let obj = out.join("demo-textured.obj");
    let bytes = crate::compile_to(&obj, &out.join("demo-textured.peel"), &options, None)?;
    let frame = render_bytes_with(&bytes, &DEMO_SHOT, settings)?;
    let png_path = out.join("demo-textured.png");
    write_png(&png_path, &frame)?;
    say(&png_path, &frame);

    let torus = peel_compiler::tools::scenes::textured_torus(24, 48);
    let smooth = CompileOptions {
        surface: Surface::Smooth(Crease::default()),
        ..CompileOptions::default()
    };
    let (_, bytes) = peel_compiler::compile::compile_mesh(&torus, &smooth, &|_| {})
        .map_err(|e| e.to_string())?;
    let shot = Shot {
        fov_y_deg: 40.0,
        ..Shot::new(DVec3::new(0.0, 2.4, 3.2), DVec3::ZERO, 800, 600)
    };
    let frame = render_bytes_with(&bytes, &shot, settings)?;
    let png_path = out.join("demo-checker.png");
    write_png(&png_path, &frame)?;
    say(&png_path, &frame);
    Ok(())
}

fn say(png: &Path, frame: &Frame) {
    println!(
        "{}: {}x{}, {} polygons drawn, {} pixels written",
        png.display(),
        frame.width,
        frame.height,
        frame.stats.polygons_drawn,
        frame.stats.pixels_written
    );
}

/// The demo with a part that moves: the torus compiled as an object of a file of parts
/// (`demo-objects.peel`), drawn where its file puts it (`demo-pose-1.png`), then stood on its
/// rim and turned (`demo-pose-2.png`). Its light is baked in its own frame, so it turns with
/// it, and it casts no shadow on the world.
fn demo_objects(out: &Path, options: &CompileOptions, settings: &Settings) -> Result<(), String> {
    let world = out.join("demo-world.obj");
    std::fs::write(&world, DEMO_OBJ).map_err(|e| format!("{}: {e}", world.display()))?;
    let torus = out.join("demo-torus.obj");
    std::fs::write(&torus, DEMO_TORUS_OBJ).map_err(|e| format!("{}: {e}", torus.display()))?;
    let objects = [("torus".to_string(), torus)];
    let compiled = peel_compiler::compile::compile_parts(Some(&world), &objects, options, &|_| {})
        .map_err(|e| e.to_string())?;
    let path = out.join("demo-objects.peel");
    peel_compiler::write::write_atomic(&path, &compiled.bytes).map_err(|e| e.to_string())?;
    let parts = Parts::parse(&compiled.bytes).map_err(|e| format!("{}: {e}", path.display()))?;
    let (world, (_, scene)) = match (parts.world(), parts.object(0)) {
        (Some(w), Some(o)) => (w, o),
        _ => return Err(format!("{}: not the demo's parts", path.display())),
    };
    // Stood on its rim (a quarter turn about x) and turned 40 degrees about the vertical,
    // about its own centre, resting on the ground.
    let centre = Vec3::new(-2.1, 0.34, 1.7);
    let stood = Vec3::new(-2.1, 1.19, 1.7);
    let turned = Pose::from_degrees(Vec3::ZERO, 40.0, 90.0, 0.0);
    let moved = Pose {
        translation: stood - turned.rotation * centre,
        ..turned
    };
    for (k, pose) in [Pose::IDENTITY, moved].into_iter().enumerate() {
        let objects = [Object::new(scene, Some(pose))];
        let frame = render_posed_named(Some(&world), &objects, &["torus"], &DEMO_SHOT, settings)?;
        let png_path = out.join(format!("demo-pose-{}.png", k + 1));
        write_png(&png_path, &frame)?;
        say(&png_path, &frame);
    }
    Ok(())
}

/// The demo scene (also `fixtures/demo.obj`).
const DEMO_OBJ: &str = include_str!("../../fixtures/demo.obj");
const DEMO_MTL: &str = include_str!("../../fixtures/demo.mtl");
/// The curved model `peel demo` adds beside the boxes (`fixtures/demo-torus.obj`, relative
/// indices: it follows demo.obj in one file). The benchmarks keep demo.obj alone.
const DEMO_TORUS_OBJ: &str = include_str!("../../fixtures/demo-torus.obj");
const DEMO_TORUS_MTL: &str = include_str!("../../fixtures/demo-torus.mtl");
/// The textured scene `peel demo` draws too (`fixtures/demo-textured.obj`), with the pictures
/// of `fixtures/textured-box/` and `fixtures/textured-floor/`.
const DEMO_TEXTURED_OBJ: &str = include_str!("../../fixtures/demo-textured.obj");
const DEMO_TEXTURED_MTL: &str = include_str!("../../fixtures/demo-textured.mtl");

/// Arguments of `peel bench`.
#[derive(Args)]
pub struct BenchArgs {
    /// `frames` (default): frame time vs error per method; `compile`: the compiler vs its baselines.
    #[arg(default_value = "frames")]
    pub what: BenchWhat,
    /// Folder of the shared models (teapot, cow, suzanne, stanford-bunny); absent models are
    /// skipped with a notice.
    #[arg(long, default_value = "../shared/models", value_name = "DIR")]
    pub models: PathBuf,
    /// Write one JSON record per (scene, method).
    #[arg(long, value_name = "FILE")]
    pub json: Option<PathBuf>,
    /// Where the markdown table and the plot go.
    #[arg(long, default_value = "peel-bench", value_name = "DIR")]
    pub out: PathBuf,
    /// Image size WxH.
    #[arg(long, value_parser = parse_size, default_value = "640x480", value_name = "WxH")]
    pub size: (u32, u32),
    /// Cameras per scene.
    #[arg(long, default_value_t = 16, value_name = "N")]
    pub cameras: usize,
    /// Only the small scenes (demo and generated), for a quick look.
    #[arg(long)]
    pub quick: bool,
}

/// What `peel bench` measures.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum BenchWhat {
    /// Frame time against pixel error.
    Frames,
    /// Compile time and output size against the baselines.
    Compile,
}

/// The demo scene as a mesh (written to a temporary folder so its MTL resolves).
fn demo_mesh() -> Result<peel_compiler::load::Mesh, String> {
    let dir = std::env::temp_dir().join(format!("peel-bench-demo-{}", std::process::id()));
    std::fs::create_dir_all(&dir).map_err(|e| e.to_string())?;
    std::fs::write(dir.join("demo.obj"), DEMO_OBJ).map_err(|e| e.to_string())?;
    std::fs::write(dir.join("demo.mtl"), DEMO_MTL).map_err(|e| e.to_string())?;
    let mesh = peel_compiler::load::load_obj(&dir.join("demo.obj")).map_err(|e| e.to_string());
    let _ = std::fs::remove_dir_all(&dir);
    mesh
}

/// The benchmark's scenes: the demo, generated scenes, then the shared models found.
fn bench_scenes(
    models: &Path,
    quick: bool,
) -> Result<Vec<(String, peel_compiler::load::Mesh)>, String> {
    use peel_compiler::tools::scenes;
    let mut v = vec![
        ("demo".to_string(), demo_mesh()?),
        ("sphere-9k".to_string(), scenes::sphere(48, 96)),
        ("torus-4k".to_string(), scenes::torus(64, 32)),
        ("box-grid-768".to_string(), scenes::box_grid(4)),
        ("soup-1k".to_string(), scenes::soup(1000, 0.25, 1)),
    ];
    if quick {
        return Ok(v);
    }
    for name in ["teapot", "suzanne", "cow", "stanford-bunny"] {
        let path = models.join(format!("{name}.obj"));
        if !path.exists() {
            eprintln!("notice: {} not found, skipping {name}", path.display());
            continue;
        }
        v.push((
            name.to_string(),
            peel_compiler::load::load_obj(&path).map_err(|e| e.to_string())?,
        ));
    }
    Ok(v)
}

/// `peel bench`.
pub fn bench(args: &BenchArgs) -> Result<(), String> {
    std::fs::create_dir_all(&args.out).map_err(|e| format!("{}: {e}", args.out.display()))?;
    match args.what {
        BenchWhat::Frames => bench_frames(args),
        BenchWhat::Compile => {
            let table = peel_compiler::tools::bench_compile::bench_compile(
                &args.models,
                args.json.as_deref(),
            )
            .map_err(|e| e.to_string())?;
            let md = args.out.join("compile.md");
            peel_compiler::write::write_atomic(&md, table.as_bytes()).map_err(|e| e.to_string())?;
            println!("{table}");
            println!("wrote {}", md.display());
            Ok(())
        }
    }
}

fn bench_frames(args: &BenchArgs) -> Result<(), String> {
    use peel_compiler::tools::bench_frames;
    let scenes: Vec<bench_frames::BenchScene> = bench_scenes(&args.models, args.quick)?
        .into_iter()
        .map(|(name, mesh)| bench_frames::frame_scene(&name, mesh, &mut |m| eprintln!("{m}")))
        .collect::<Result<_, _>>()?;
    let (w, h) = args.size;
    let mut records = bench_frames::run(&scenes, w, h, args.cameras, &mut |m| eprintln!("{m}"))?;
    let mut report = format!(
        "## Frame time vs error ({w}x{h}, {} cameras per scene)\n\n",
        args.cameras
    );
    report += &bench_frames::markdown(&records);
    // The transparent scenes, with the z-buffer that sorts transparent triangles each frame.
    let transparent =
        peel_compiler::tools::scenes::transparent_scenes(Some(&args.models), &mut |m| {
            eprintln!("{m}")
        })
        .map_err(|e| e.to_string())?;
    let composited = bench_frames::run_transparent(&transparent, &mut |m| eprintln!("{m}"))?;
    report += &format!(
        "\n## Transparent surfaces (160x120, 4 views per scene; wrong: a channel more than {} \
         from the composited ray cast)\n\n",
        bench_frames::TOLERANCE
    );
    report += &bench_frames::markdown(&composited);
    // (The plot is of the opaque scenes'.)
    let opaque = records.len();
    records.extend(composited);
    let knob_scene = scenes
        .iter()
        .find(|s| s.name == "cow")
        .or_else(|| scenes.iter().find(|s| s.name == "sphere-9k"));
    if let Some(s) = knob_scene {
        report += "\n## The --candidates knob\n\n";
        report += &bench_frames::candidates_knob(
            &s.name,
            &s.mesh,
            &[4, 16, 64, 256],
            w,
            h,
            args.cameras,
        )?;
    }
    let md = args.out.join("frames.md");
    peel_compiler::write::write_atomic(&md, report.as_bytes()).map_err(|e| e.to_string())?;
    let png = args.out.join("frames.png");
    peel_compiler::write::write_atomic(&png, &bench_frames::plot(&records[..opaque])?)
        .map_err(|e| e.to_string())?;
    if let Some(json) = &args.json {
        let text = bench_frames::json(&records)?;
        peel_compiler::write::write_atomic(json, text.as_bytes()).map_err(|e| e.to_string())?;
    }
    println!("{report}");
    println!("wrote {} and {}", md.display(), png.display());
    Ok(())
}
