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

/// Whether `r` is a plotted record of `scene` at 320x240 (flat shading), and its method's
/// index.
pub fn plotted(r: &Record, scene: &str) -> Option<usize> {
    if r.scene != scene || (r.width, r.height) != (320, 240) || !r.is_flat() {
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
    peel_compiler::tools::bench_frames::bitmap_png(900, 600, |root| {
        // Whole decades around the points.
        let bound = |f: fn(&Record) -> u64| {
            let v = points.iter().map(|(r, _)| f(r) as f64);
            let lo = v.clone().fold(f64::INFINITY, f64::min).max(1.0);
            let hi = v.fold(1.0, f64::max);
            10f64.powf(lo.log10().floor())..10f64.powf(hi.log10().ceil() + 0.5)
        };
        let mut chart = ChartBuilder::on(root)
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
            .x_labels(4)
            .y_labels(5)
            .x_label_formatter(&|v| format!("{:.0} kB", v / 1000.0))
            .y_label_formatter(&|v| format!("{:.0} M", v / 1e6))
            .draw()
            .map_err(|e| e.to_string())?;
        // One series per method (its colour), a circle on the Cortex-M4F and a triangle on the
        // Cortex-M0+; the legend names the method and its robust errors.
        for (k, (name, _, [red, green, blue])) in METHODS.iter().enumerate() {
            let colour = RGBColor(*red, *green, *blue);
            let mine: Vec<&Record> = points
                .iter()
                .filter(|(_, m)| *m == k)
                .map(|(r, _)| *r)
                .collect();
            let Some(first) = mine.first() else {
                continue;
            };
            let at = |r: &Record| (r.ram_bytes as f64, r.instructions as f64);
            let errors = mine
                .iter()
                .filter_map(|r| r.robust_errors)
                .max()
                .unwrap_or(0);
            chart
                .draw_series(
                    mine.iter()
                        .filter(|r| r.core == "cortex-m4f")
                        .map(|r| Circle::new(at(r), 7, colour.filled())),
                )
                .map_err(|e| e.to_string())?
                .label(format!(
                    "{name} ({}, {errors} robust errors)",
                    first
                        .path
                        .replace(char::is_numeric, "")
                        .trim_end_matches('-')
                ))
                .legend(move |(x, y)| Circle::new((x, y), 5, colour.filled()));
            chart
                .draw_series(
                    mine.iter()
                        .filter(|r| r.core != "cortex-m4f")
                        .map(|r| TriangleMarker::new(at(r), 8, colour.filled())),
                )
                .map_err(|e| e.to_string())?;
        }
        // The cores' shapes.
        for (core, m4f) in [
            ("circle: Cortex-M4F", true),
            ("triangle: Cortex-M0+", false),
        ] {
            chart
                .draw_series(std::iter::empty::<Circle<(f64, f64), i32>>())
                .map_err(|e| e.to_string())?
                .label(core)
                .legend(
                    move |(x, y)| -> DynElement<'static, BitMapBackend, (i32, i32)> {
                        if m4f {
                            Circle::new((x, y), 5, BLACK.filled()).into_dyn()
                        } else {
                            TriangleMarker::new((x, y), 6, BLACK.filled()).into_dyn()
                        }
                    },
                );
        }
        chart
            .configure_series_labels()
            .position(SeriesLabelPosition::UpperRight)
            .background_style(WHITE.mix(0.9))
            .border_style(BLACK)
            .label_font(("sans-serif", 14))
            .draw()
            .map_err(|e| e.to_string())?;
        Ok(())
    })
    .map(Some)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn record(method: &str, path: &str, core: &str, ram: u64, instructions: u64) -> Record {
        Record {
            scene: "teapot".into(),
            method: method.into(),
            path: path.into(),
            shading: "flat".into(),
            core: core.into(),
            width: 320,
            height: 240,
            triangles: 6320,
            instructions,
            ram_bytes: ram,
            framebuffer_bytes: 0,
            flash_bytes: 400_000,
            text_bytes: 40_000,
            display_bytes: 153_611,
            display_writes: 2,
            differing_pixels: Some(0),
            robust_errors: Some(0),
            pending_peak: None,
            pending_records: None,
            pending_fallback: None,
            deterministic: true,
            objects: 0,
            transparent: false,
            fallback_rows: None,
            composite_peak: None,
            composite_runs: None,
        }
    }

    #[test]
    fn plots_the_methods_of_one_scene() {
        let records = [
            record(
                "peel-front-to-back",
                "stream",
                "cortex-m4f",
                28_752,
                15_717_120,
            ),
            record(
                "peel-front-to-back",
                "stream",
                "cortex-m0plus",
                29_320,
                60_696_920,
            ),
            record(
                "embedded-3dgfx",
                "framebuffer",
                "cortex-m4f",
                456_636,
                8_456_920,
            ),
            record(
                "tiled-zbuffer",
                "bands-20",
                "cortex-m4f",
                27_720,
                46_829_040,
            ),
            // Not plotted: another path of Peel.
            record(
                "peel-front-to-back",
                "framebuffer",
                "cortex-m4f",
                182_000,
                16_000_000,
            ),
        ];
        assert_eq!(plotted(&records[3], "teapot"), Some(3));
        assert_eq!(plotted(&records[4], "teapot"), None);
        assert_eq!(plotted(&records[0], "cow"), None);
        // A smooth record is not the flat one's point.
        let mut smooth = records[0].clone();
        smooth.shading = "smooth".into();
        assert_eq!(plotted(&smooth, "teapot"), None);
        let png = plot(&records, "teapot").unwrap().unwrap();
        let image = image::load_from_memory(&png).unwrap();
        assert_eq!((image.width(), image.height()), (900, 600));
        assert!(plot(&records, "cow").unwrap().is_none());
    }
}
