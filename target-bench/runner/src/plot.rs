//! The plot a user decides from: instructions per frame against RAM, log scales, one marker
//! per method and core, for one scene at 320x240 (each method's own display path: Peel
//! streamed, the z-buffers as they send their frames).

use crate::results::Record;

/// The methods plotted and in the alternatives table, with their colour: Peel front to back
/// streamed, and the peers.
pub const METHODS: [(&str, &str, [u8; 3]); 5] = [
    ("peel-front-to-back", "stream", [200, 30, 30]),
    ("embedded-3dgfx", "framebuffer", [30, 80, 200]),
    ("zbuffer-int", "framebuffer", [40, 150, 60]),
    ("tiled-zbuffer", "bands-", [150, 60, 170]),
    ("scanline-zbuffer", "bands-1", [220, 130, 0]),
];

/// Whether `r` is a plotted record of `scene` at 320x240, and its method's index.
pub fn plotted(r: &Record, scene: &str) -> Option<usize> {
    if r.scene != scene || (r.width, r.height) != (320, 240) {
        return None;
    }
    METHODS
        .iter()
        .position(|(m, path, _)| r.method == *m && r.path.starts_with(path))
}

/// The PNG bytes of the plot of `scene`'s records, `None` when it has none.
pub fn plot(records: &[Record], scene: &str) -> Result<Option<Vec<u8>>, String> {
    use plotters::prelude::*;
    let points: Vec<(&Record, usize)> = records
        .iter()
        .filter_map(|r| Some((r, plotted(r, scene)?)))
        .collect();
    if points.is_empty() {
        return Ok(None);
    }
    static FONT: std::sync::OnceLock<Result<(), String>> = std::sync::OnceLock::new();
    FONT.get_or_init(|| {
        // plotters draws text with ab_glyph from a font we ship: no system font is needed.
        plotters::style::register_font("sans-serif", FontStyle::Normal, dejavu::sans::regular())
            .map_err(|_| "cannot load the plot font".to_string())
    })
    .clone()?;
    let (w, h) = (900u32, 600u32);
    let mut rgb = vec![255u8; (w * h * 3) as usize];
    {
        let root = BitMapBackend::with_buffer(&mut rgb, (w, h)).into_drawing_area();
        root.fill(&WHITE).map_err(|e| e.to_string())?;
        let bound = |f: fn(&Record) -> u64| {
            let v = points.iter().map(|(r, _)| f(r) as f64);
            let lo = v.clone().fold(f64::INFINITY, f64::min) / 2.0;
            let hi = v.fold(1.0, f64::max) * 2.0;
            lo.max(1.0)..hi
        };
        let mut chart = ChartBuilder::on(&root)
            .caption(
                format!("{scene} at 320x240: instructions per frame against RAM"),
                ("sans-serif", 22),
            )
            .margin(15)
            .x_label_area_size(45)
            .y_label_area_size(70)
            .build_cartesian_2d(
                bound(|r| r.ram_bytes).log_scale(),
                bound(|r| r.instructions).log_scale(),
            )
            .map_err(|e| e.to_string())?;
        chart
            .configure_mesh()
            .x_desc("RAM (bytes)")
            .y_desc("instructions per frame (median of the cameras)")
            .x_label_formatter(&|v| format!("{:.0} kB", v / 1000.0))
            .y_label_formatter(&|v| format!("{:.1} M", v / 1e6))
            .draw()
            .map_err(|e| e.to_string())?;
        for (r, k) in &points {
            let (name, _, [red, green, blue]) = METHODS[*k];
            let colour = RGBColor(red, green, blue);
            let at = (r.ram_bytes as f64, r.instructions as f64);
            let m4f = r.core == "cortex-m4f";
            if m4f {
                chart
                    .draw_series([Circle::new(at, 7, colour.filled())])
                    .map_err(|e| e.to_string())?;
            } else {
                chart
                    .draw_series([TriangleMarker::new(at, 8, colour.filled())])
                    .map_err(|e| e.to_string())?;
            }
            let core = if m4f { "M4F" } else { "M0+" };
            let label = format!("{name}, {core}, {} errors", r.robust_errors);
            chart
                .draw_series([Text::new(
                    label,
                    at,
                    ("sans-serif", 14).into_font().color(&colour),
                )])
                .map_err(|e| e.to_string())?;
        }
        root.present().map_err(|e| e.to_string())?;
    }
    let image =
        image::RgbImage::from_raw(w, h, rgb).ok_or("plot: the buffer is not the image's size")?;
    let mut png = Vec::new();
    image
        .write_to(&mut std::io::Cursor::new(&mut png), image::ImageFormat::Png)
        .map_err(|e| e.to_string())?;
    Ok(Some(png))
}
