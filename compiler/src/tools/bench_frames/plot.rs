//! The plot of the measurements: frame time against pixel errors, one colour per method.

use super::{FrameRecord, Method};

/// A marker shape of the plot.
#[derive(Debug, Clone, Copy)]
enum Marker {
    Dot,
    Triangle,
    Cross,
}

impl Marker {
    fn of(method: Method) -> Marker {
        match method {
            Method::Watkins | Method::WarnockQuadrants | Method::WarnockEnclosing => {
                Marker::Triangle
            }
            Method::WeilerAtherton => Marker::Cross,
            _ => Marker::Dot,
        }
    }

    /// The marker at `at` (data or pixel coordinates, as the series or legend gives).
    fn draw<DB, C>(
        self,
        at: C,
        style: plotters::style::ShapeStyle,
    ) -> plotters::element::DynElement<'static, DB, C>
    where
        DB: plotters::prelude::DrawingBackend,
        C: Clone + 'static,
    {
        use plotters::prelude::*;
        match self {
            Marker::Dot => Circle::new(at, 5, style).into_dyn(),
            Marker::Triangle => TriangleMarker::new(at, 7, style).into_dyn(),
            Marker::Cross => Cross::new(at, 6, style.stroke_width(2)).into_dyn(),
        }
    }
}

/// The PNG bytes of a `width x height` plot on white that `draw` draws, with the font the
/// project ships (plotters draws text with ab_glyph: no system font is needed). The one
/// canvas of every plot (`peel bench`'s, the on-target benchmark's).
pub fn bitmap_png(
    width: u32,
    height: u32,
    draw: impl FnOnce(
        &plotters::drawing::DrawingArea<
            plotters::prelude::BitMapBackend<'_>,
            plotters::coord::Shift,
        >,
    ) -> Result<(), String>,
) -> Result<Vec<u8>, String> {
    use plotters::prelude::*;
    static FONT: std::sync::OnceLock<Result<(), String>> = std::sync::OnceLock::new();
    FONT.get_or_init(|| {
        plotters::style::register_font("sans-serif", FontStyle::Normal, dejavu::sans::regular())
            .map_err(|_| "cannot load the plot font".to_string())
    })
    .clone()?;
    let mut rgb = vec![255u8; (width * height * 3) as usize];
    {
        let root = BitMapBackend::with_buffer(&mut rgb, (width, height)).into_drawing_area();
        root.fill(&WHITE).map_err(|e| e.to_string())?;
        draw(&root)?;
        root.present().map_err(|e| e.to_string())?;
    }
    let frame = crate::tools::raster::Frame {
        width,
        height,
        pixels: rgb
            .chunks(3)
            .map(|c| (u32::from(c[0]) << 16) | (u32::from(c[1]) << 8) | u32::from(c[2]))
            .collect(),
        stats: Default::default(),
    };
    crate::tools::raster::png(&frame)
}

/// A scatter plot (PNG bytes) of median frame time against all errors, one colour per method.
pub fn plot(records: &[FrameRecord]) -> Result<Vec<u8>, String> {
    use plotters::prelude::*;
    bitmap_png(900, 600, |root| {
        let max_t = records
            .iter()
            .map(|r| r.median_frame_ms)
            .fold(1e-3, f64::max)
            * 2.0;
        let min_t = records
            .iter()
            .map(|r| r.median_frame_ms)
            .fold(max_t, f64::min)
            .max(1e-4)
            / 2.0;
        let max_e = records
            .iter()
            .map(|r| r.all_errors)
            .max()
            .unwrap_or(1)
            .max(1) as f64
            * 2.0;
        let mut chart = ChartBuilder::on(root)
            .caption(
                "frame time vs pixel errors (16 cameras per scene)",
                ("sans-serif", 22),
            )
            .margin(15)
            .x_label_area_size(45)
            .y_label_area_size(60)
            .build_cartesian_2d((min_t..max_t).log_scale(), (0.5f64..max_e).log_scale())
            .map_err(|e| e.to_string())?;
        chart
            .configure_mesh()
            .x_desc("median frame time (ms)")
            .y_desc("mismatched pixels + 1 (all)")
            .draw()
            .map_err(|e| e.to_string())?;
        // Peel and the first baselines as dots, the survey's methods as triangles (Watkins,
        // Warnock) and a cross (Weiler-Atherton), so ten methods stay apart.
        let palette = [
            RED,
            BLUE,
            GREEN,
            MAGENTA,
            CYAN,
            BLACK,
            RGBColor(230, 120, 0),
            RGBColor(120, 60, 160),
            RGBColor(140, 90, 40),
            RGBColor(90, 130, 0),
        ];
        for (k, m) in Method::ALL.into_iter().enumerate() {
            let style = palette[k % palette.len()].filled();
            let pts: Vec<(f64, f64)> = records
                .iter()
                .filter(|r| r.method == m.name())
                .map(|r| (r.median_frame_ms, r.all_errors as f64 + 1.0))
                .collect();
            let marker = Marker::of(m);
            chart
                .draw_series(pts.iter().map(|&p| marker.draw(p, style)))
                .map_err(|e| e.to_string())?
                .label(m.name())
                .legend(move |p| marker.draw(p, style));
        }
        chart
            .configure_series_labels()
            .background_style(WHITE.mix(0.8))
            .border_style(BLACK)
            .draw()
            .map_err(|e| e.to_string())?;
        Ok(())
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn plot_is_a_png() {
        let r = FrameRecord {
            scene: "s".into(),
            method: "zbuffer-int".into(),
            median_frame_ms: 1.0,
            pixels_written: 10,
            robust_errors: 0,
            all_errors: 3,
            memory_bytes: 1,
            polygons_drawn: 0,
        };
        let png = plot(&[r]).unwrap();
        assert_eq!(&png[1..4], b"PNG");
    }
}
