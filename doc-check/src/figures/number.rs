//! Figures as prose quotes them: `25,048 B`, `21-25 kB`, `15.3M`, `1.7-1.8x`.

/// A unit: what the value is divided by, its suffix, and the decimals it gets by default
/// (`None`: integers as they are, other values to 3 significant digits).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Unit {
    /// The name in a marker (`unit=kB`).
    pub name: &'static str,
    divisor: f64,
    suffix: &'static str,
    decimals: Option<usize>,
}

/// The units of `unit=`.
pub const UNITS: [Unit; 9] = [
    Unit {
        name: "",
        divisor: 1.0,
        suffix: "",
        decimals: None,
    },
    Unit {
        name: "B",
        divisor: 1.0,
        suffix: " B",
        decimals: None,
    },
    Unit {
        name: "kB",
        divisor: 1e3,
        suffix: " kB",
        decimals: Some(0),
    },
    Unit {
        name: "KiB",
        divisor: 1024.0,
        suffix: " KiB",
        decimals: Some(0),
    },
    Unit {
        name: "MB",
        divisor: 1e6,
        suffix: " MB",
        decimals: Some(1),
    },
    Unit {
        name: "M",
        divisor: 1e6,
        suffix: "M",
        decimals: Some(1),
    },
    Unit {
        name: "s",
        divisor: 1.0,
        suffix: " s",
        decimals: Some(1),
    },
    Unit {
        name: "ms",
        divisor: 1.0,
        suffix: " ms",
        decimals: Some(3),
    },
    Unit {
        name: "x",
        divisor: 1.0,
        suffix: "x",
        decimals: None,
    },
];

/// How many digits a figure keeps.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Precision {
    /// The unit's default.
    Default,
    /// Decimals after the point (`digits=N`).
    Decimals(usize),
    /// Significant digits (`sig=N`).
    Significant(usize),
}

/// The unit named `name`.
pub fn unit(name: &str) -> Result<Unit, String> {
    UNITS
        .iter()
        .copied()
        .find(|u| u.name == name)
        .ok_or_else(|| {
            let names: Vec<&str> = UNITS.iter().skip(1).map(|u| u.name).collect();
            format!("unit={name}: not a unit ({})", names.join(", "))
        })
}

/// `text` with `,` between thousands of its integer part (`-1234567.5` gives
/// `-1,234,567.5`).
fn thousands(text: &str) -> String {
    let (sign, rest) = text.strip_prefix('-').map_or(("", text), |r| ("-", r));
    let (int, frac) = rest
        .split_once('.')
        .map_or((rest, None), |(i, f)| (i, Some(f)));
    let mut out = String::from(sign);
    for (i, c) in int.chars().enumerate() {
        if i > 0 && (int.len() - i) % 3 == 0 {
            out.push(',');
        }
        out.push(c);
    }
    if let Some(f) = frac {
        out.push('.');
        out.push_str(f);
    }
    out
}

/// `v` to `sig` significant digits, as text (`0.3121` to 2 gives `0.31`, `18.3` gives `18`,
/// `1234` gives `1200`).
fn significant(v: f64, sig: usize) -> String {
    if v == 0.0 || !v.is_finite() {
        return format!("{v}");
    }
    let sig = sig.max(1) as i32;
    let magnitude = v.abs().log10().floor() as i32;
    let scale = 10f64.powi(sig - 1 - magnitude);
    let rounded = (v * scale).round() / scale;
    // Rounding may carry into another digit (9.96 to 2 gives 10).
    let magnitude = rounded.abs().log10().floor() as i32;
    let decimals = (sig - 1 - magnitude).max(0) as usize;
    format!("{rounded:.decimals$}")
}

/// `v` in `unit` at `precision`, without the suffix.
fn number(v: f64, unit: Unit, precision: Precision) -> String {
    let v = v / unit.divisor;
    let text = match (precision, unit.decimals) {
        (Precision::Decimals(d), _) | (Precision::Default, Some(d)) => format!("{v:.d$}"),
        (Precision::Significant(s), _) => significant(v, s),
        (Precision::Default, None) if v.fract() == 0.0 && v.abs() < 1e15 => format!("{v:.0}"),
        (Precision::Default, None) => significant(v, 3),
    };
    thousands(&text)
}

/// The values as one figure (`25 kB`) or the range they span (`21-25 kB`).
pub fn range(values: &[f64], unit: Unit, precision: Precision) -> String {
    let lo = values.iter().copied().fold(f64::INFINITY, f64::min);
    let hi = values.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    let (a, b) = (number(lo, unit, precision), number(hi, unit, precision));
    if a == b {
        format!("{a}{}", unit.suffix)
    } else {
        format!("{a}-{b}{}", unit.suffix)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn figures_as_prose_quotes_them() {
        let u = |n| unit(n).unwrap();
        let d = Precision::Default;
        assert_eq!(range(&[25_048.0], u("B"), d), "25,048 B");
        assert_eq!(range(&[1247.0], u(""), d), "1,247");
        assert_eq!(
            range(&[24_920.0, 21_080.0, 25_272.0], u("kB"), d),
            "21-25 kB"
        );
        assert_eq!(range(&[15_136_880.0], u("M"), d), "15.1M");
        assert_eq!(range(&[1.4004], u("s"), d), "1.4 s");
        assert_eq!(
            range(&[1.718, 1.882, 1.779], u(""), Precision::Decimals(2)),
            "1.72-1.88"
        );
        assert_eq!(
            range(&[1.806, 1.739], u("x"), Precision::Significant(2)),
            "1.7-1.8x"
        );
        assert_eq!(
            range(&[0.3121, 0.349], u("x"), Precision::Significant(2)),
            "0.31-0.35x"
        );
        assert_eq!(
            range(&[18.3, 21.4], u("x"), Precision::Significant(2)),
            "18-21x"
        );
        assert_eq!(range(&[1.2374], u("x"), Precision::Significant(3)), "1.24x");
        assert_eq!(range(&[1.2374], u("x"), d), "1.24x");
        assert_eq!(range(&[9.96], u("x"), Precision::Significant(2)), "10x");
        assert_eq!(range(&[1234.0], u(""), Precision::Significant(2)), "1,200");
        assert_eq!(range(&[0.0], u(""), d), "0");
        assert_eq!(
            range(&[-1234567.5], u(""), Precision::Decimals(1)),
            "-1,234,567.5"
        );
        assert!(unit("GB")
            .unwrap_err()
            .contains("not a unit (B, kB, KiB, MB, M, s, ms, x)"));
    }
}
