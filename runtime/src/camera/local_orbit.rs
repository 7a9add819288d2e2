//! [`LocalOrbit`]: the orbit of [`super::Orbit`] made in `f32` alone, in a scene's local frame.
//!
//! [`super::Orbit`] and [`super::Camera::look_at`] compute in `f64` with libm's `sin`, `cos`,
//! `tan` and `sqrt`: on a core without `f64` hardware (Cortex-M0+, Cortex-M4F) that links
//! software floating point and libm. A [`LocalOrbit`] gives the same view (within the bounds
//! below) with `f32` arithmetic only: its sines and cosines are polynomials, its one square
//! root (the scene's bounding radius) a few Newton steps, and its basis is written out (the
//! orbit fixes it), so firmware that draws an orbit this way links neither `f64` arithmetic
//! nor any libm function.
//!
//! # What it guarantees
//!
//! * [`sin_cos_deg`] is within `4e-7` of the exact sine and cosine for angles up to
//!   `±16,000,000` degrees (the argument is reduced exactly to a quarter turn, then two short
//!   Taylor polynomials whose truncation error is below `2e-9`); exact (`0`, `±1`) at multiples
//!   of 90 degrees.
//! * [`LocalOrbit::view`] agrees with the `f64` path,
//!   `Camera::look_at(orbit.pose(&header), fov, w, h, near).view(header.centre)` for the same
//!   angles and distance and the focal length of `fov` ([`LocalOrbit::focal`]): each basis
//!   component within `2e-6`, the eye within `2e-6` of the scene's reach (`|bounds|` plus the
//!   eye's distance from the box centre) per component, the focal length, principal point and
//!   near distance within `f32` rounding (tested in `camera::tests`). Projected points move by
//!   that error times the focal length: thousandths of a pixel at 320x240. So the pixels are
//!   the same except where an edge passes within that distance of a pixel centre, and such a
//!   pixel takes the colour of a neighbour across that edge: not the same image bit for bit,
//!   but no visible difference (over the tests' 144 frames of two boxes, 2 of 1.6 million
//!   pixels differ).
//! * Unlike the `f64` orbit it takes an elevation of `±90` degrees: `right` comes from the
//!   azimuth alone, so the view straight down or up is still defined (turned by the azimuth).

use glam::Vec3;

use super::LocalView;
use crate::error::RenderError;
use crate::read::Header;

/// `π / 180` rounded to `f32`.
const RADIANS_PER_DEGREE: f32 = core::f32::consts::PI / 180.0;

/// The sine and cosine of `deg` degrees, in `f32` alone (no libm): within `4e-7` of the exact
/// values for `|deg| <= 16,000,000` (see the module docs); beyond that the reduction to a
/// quarter turn is no longer exact and the error grows with the angle's rounding. A NaN or
/// infinite angle gives NaNs.
pub fn sin_cos_deg(deg: f32) -> (f32, f32) {
    if !deg.is_finite() {
        return (f32::NAN, f32::NAN);
    }
    // The nearest multiple of 90 degrees, `n * 90`, and the rest `r` in [-45, 45]: `n * 90` is
    // exact below 2^24, and `deg - n * 90` is then exact (Sterbenz: the two are within a
    // factor 2 of each other, or `n` is 0).
    let q = deg * (1.0 / 90.0);
    let n = if q >= 0.0 { q + 0.5 } else { q - 0.5 } as i32;
    let r = (deg - n as f32 * 90.0) * RADIANS_PER_DEGREE;
    let r2 = r * r;
    // Taylor to `r^9` and `r^10`: at |r| <= π/4 the next terms are below 2e-9 and 2e-10.
    let s = r
        * (1.0
            - r2 * (1.0 / 6.0)
                * (1.0
                    - r2 * (1.0 / 20.0) * (1.0 - r2 * (1.0 / 42.0) * (1.0 - r2 * (1.0 / 72.0)))));
    let c = 1.0
        - r2 * 0.5
            * (1.0
                - r2 * (1.0 / 12.0)
                    * (1.0
                        - r2 * (1.0 / 30.0)
                            * (1.0 - r2 * (1.0 / 56.0) * (1.0 - r2 * (1.0 / 90.0)))));
    match n & 3 {
        0 => (s, c),
        1 => (c, -s),
        2 => (-s, -c),
        _ => (-c, s),
    }
}

/// The square root of `x` in `f32` alone (no libm): a first guess from the exponent's bits,
/// then Newton steps. Within `2^-22` of `√x`, relatively, for normal `x`; 0 for `x <= 0` or
/// NaN, `x` for `+∞`.
pub(crate) fn sqrt(x: f32) -> f32 {
    if x.is_nan() || x <= 0.0 {
        return 0.0;
    }
    if x == f32::INFINITY {
        return x;
    }
    // Halving the biased exponent (and, roughly, the mantissa): within 6% of `√x`; each
    // Newton step squares the relative error (6e-2, 2e-3, 2e-6, 2e-12), and a subnormal
    // `x`, whose guess is further off, gets more steps.
    let mut y = f32::from_bits((x.to_bits() >> 1) + 0x1fbb_4f2e);
    let steps = if x < f32::MIN_POSITIVE { 24 } else { 4 };
    for _ in 0..steps {
        y = 0.5 * (y + x / y);
    }
    y
}

/// The orbit of [`super::Orbit`] in `f32` alone: the eye on a sphere around the centre of the
/// scene's bounding box, looking at that centre, up `0,1,0`; made into a [`LocalView`] (the
/// scene's local frame) with no `f64` arithmetic and no libm (see the module docs for how
/// close it stays to the `f64` path).
///
/// ```
/// use peel_runtime::camera::LocalOrbit;
/// # let header = peel_runtime::read::Header {
/// #     bounds_min: glam::Vec3::splat(-1.0), bounds_max: glam::Vec3::splat(1.0),
/// #     ..Default::default()
/// # };
/// let (w, h) = (320, 240);
/// let focal = LocalOrbit::focal(60.0, h);
/// let mut orbit = LocalOrbit {
///     distance: LocalOrbit::fitting_distance(focal, w, h),
///     ..LocalOrbit::default()
/// };
/// let near = LocalOrbit::default_near(&header);
/// for _frame in 0..3 {
///     let view = orbit.view(&header, focal, w, h, near).expect("a valid view");
///     // renderer.draw(&scene, &view, &mut sink)?;
///     orbit.azimuth_deg += 3.0;
/// }
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LocalOrbit {
    /// Degrees around the vertical (`y`) axis, from `+z` towards `+x`.
    pub azimuth_deg: f32,
    /// Degrees above the horizontal plane, from -90 to 90 (both included: see the module
    /// docs).
    pub elevation_deg: f32,
    /// Distance of the eye from the box centre, in bounding radii (half the box diagonal).
    pub distance: f32,
}

impl Default for LocalOrbit {
    /// [`super::Orbit::default`]'s view: azimuth 30, elevation 20, 2.5 bounding radii.
    fn default() -> Self {
        LocalOrbit {
            azimuth_deg: 30.0,
            elevation_deg: 20.0,
            distance: 2.5,
        }
    }
}

impl LocalOrbit {
    /// The focal length in pixels of a vertical field of view of `fov_y_deg` degrees over
    /// `height` rows: `(height / 2) / tan(fov_y_deg / 2)`, as [`super::Camera::look_at`]
    /// takes it. Not finite or not positive for a field of view outside `(0, 180)`.
    pub fn focal(fov_y_deg: f32, height: u32) -> f32 {
        let (s, c) = sin_cos_deg(fov_y_deg * 0.5);
        height as f32 * 0.5 * c / s
    }

    /// [`super::Orbit::fitting_distance`] for the field of view of `focal` (pixels): the
    /// smallest distance, in bounding radii, at which the bounding sphere fits the image, plus
    /// 5% of margin. The half angle of the image's smaller side `m` has sine
    /// `m / √(m² + focal²)`.
    pub fn fitting_distance(focal: f32, width: u32, height: u32) -> f32 {
        let half = width.max(1).min(height.max(1)) as f32 * 0.5;
        1.05 * sqrt(half * half + focal * focal) / half
    }

    /// The bounding sphere of a scene in its local frame: its box's centre (relative to the
    /// header's `centre`) and half diagonal (1 for a scene without extent, as
    /// [`super::Orbit::bounding_sphere`]).
    pub fn bounding_sphere(header: &Header) -> (Vec3, f32) {
        let (lo, hi) = (header.bounds_min, header.bounds_max);
        let d = hi - lo;
        let radius = sqrt(d.dot(d)) * 0.5;
        ((lo + hi) * 0.5, if radius > 0.0 { radius } else { 1.0 })
    }

    /// [`super::Camera::default_near`] in `f32`: a thousandth of the box diagonal.
    pub fn default_near(header: &Header) -> f32 {
        let d = header.bounds_max - header.bounds_min;
        sqrt(d.dot(d)) * super::DEFAULT_NEAR_FRACTION as f32
    }

    /// The view of this orbit around the scene whose header is `header`: focal length `focal`
    /// in pixels (square pixels, [`LocalOrbit::focal`] from a field of view), the principal
    /// point at the centre of the `width x height` image, near distance `near`. Refuses
    /// ([`RenderError::BadCamera`]) what [`LocalView::check`] refuses: a zero-size image, a
    /// focal length or near distance that is not positive, a non-finite value (an angle,
    /// distance or bound that is not finite).
    pub fn view(
        &self,
        header: &Header,
        focal: f32,
        width: u32,
        height: u32,
        near: f32,
    ) -> Result<LocalView, RenderError> {
        let (centre, radius) = LocalOrbit::bounding_sphere(header);
        let (sa, ca) = sin_cos_deg(self.azimuth_deg);
        let (se, ce) = sin_cos_deg(self.elevation_deg);
        // From the centre towards the eye; the camera looks back along it.
        let out = Vec3::new(ce * sa, se, ce * ca);
        let eye = centre + out * (self.distance * radius);
        // `normalize(forward × up)` for `up = y`: `(ce ca, 0, -ce sa) / ce`, which is exact
        // without the division and defined at the poles too.
        let right = Vec3::new(ca, 0.0, -sa);
        let view = LocalView::from_basis(eye, right, -out, focal, width, height, near);
        view.check()?;
        Ok(view)
    }
}
