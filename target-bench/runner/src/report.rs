//! What the firmware prints over semihosting (see `target-bench/firmware/src/main.rs`), parsed.

/// One timed frame.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Frame {
    /// SysTick ticks (one per 40 instructions under `-icount shift=0`).
    pub ticks: u64,
    /// Bytes sent to the mock display.
    pub display_bytes: u64,
    /// Separate driver writes to the mock display: window set-ups and pixel runs.
    pub display_writes: u64,
    /// Front to back ran out of span memory.
    pub fallback: bool,
}

/// One frame's composite memory (the streamed build with transparency).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct CompositeUse {
    /// Rows that fell back to screen-door transparency.
    pub fallback_rows: u64,
    /// The most composite runs held at once.
    pub composite_peak: u64,
    /// The runs there are.
    pub composite_runs: u64,
}

/// One anti-aliased frame's pending pixels (stream-aa).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Antialiasing {
    /// The renderer says the frame was anti-aliased (`FrameStats::antialiased`).
    pub antialiased: bool,
    /// The most pending-pixel records the frame held at once.
    pub pending_peak: u64,
    /// The records the firmware has.
    pub pending_records: u64,
}

/// A whole run's report.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Report {
    /// The build's variant name.
    pub variant: String,
    /// The build's target triple.
    pub target: String,
    /// The frames, in camera order.
    pub frames: Vec<Frame>,
    /// Bytes taken from the firmware's pools.
    pub pool_used: u64,
    /// Bytes of the pools (statics in `.bss`, of which only `pool_used` is needed).
    pub pool_capacity: u64,
    /// Bytes of pixel memory (framebuffer or band buffer).
    pub framebuffer: u64,
    /// The stack's high-water mark over the frames, in bytes.
    pub stack_peak: u64,
    /// embedded-3dgfx: the most commands a frame recorded.
    pub gfx3d_commands: Option<u64>,
    /// stream-aa: each frame's pending pixels, in camera order (empty for other builds).
    pub antialiasing: Vec<Antialiasing>,
    /// The build with transparency: each frame's composite memory, in camera order (empty for
    /// other builds).
    pub composite: Vec<CompositeUse>,
}

/// `key=value` fields of a line, after its first word.
fn field(line: &str, key: &str) -> Result<u64, String> {
    line.split_whitespace()
        .filter_map(|w| w.split_once('='))
        .find(|(k, _)| *k == key)
        .ok_or_else(|| format!("no {key}= in {line:?}"))?
        .1
        .parse()
        .map_err(|e| format!("{key} in {line:?}: {e}"))
}

fn text(line: &str, key: &str) -> Result<String, String> {
    line.split_whitespace()
        .filter_map(|w| w.split_once('='))
        .find(|(k, _)| *k == key)
        .map(|(_, v)| v.to_string())
        .ok_or_else(|| format!("no {key}= in {line:?}"))
}

/// Parse the firmware's output. An `error:` line is the firmware's own failure and is
/// returned as the error; so is an output without its final `done` line (a crash or a
/// timeout) or with frames out of order.
pub fn parse(output: &str) -> Result<Report, String> {
    if let Some(line) = output.lines().find(|l| l.starts_with("error:")) {
        return Err(format!("the firmware reports {line:?}"));
    }
    let mut report = Report {
        variant: String::new(),
        target: String::new(),
        frames: Vec::new(),
        pool_used: 0,
        pool_capacity: 0,
        framebuffer: 0,
        stack_peak: 0,
        gfx3d_commands: None,
        antialiasing: Vec::new(),
        composite: Vec::new(),
    };
    let (mut memory, mut done) = (false, false);
    for line in output.lines() {
        match line.split_whitespace().next() {
            Some("peel-target") => {
                report.variant = text(line, "variant")?;
                report.target = text(line, "target")?;
            }
            Some("frame") => {
                let k: usize = line
                    .split_whitespace()
                    .nth(1)
                    .and_then(|k| k.parse().ok())
                    .ok_or_else(|| format!("no frame number in {line:?}"))?;
                if k != report.frames.len() {
                    return Err(format!(
                        "frame {k} where frame {} was due",
                        report.frames.len()
                    ));
                }
                report.frames.push(Frame {
                    ticks: field(line, "ticks")?,
                    display_bytes: field(line, "display_bytes")?,
                    display_writes: field(line, "display_writes")?,
                    fallback: field(line, "fallback")? != 0,
                });
            }
            Some("memory") => {
                report.pool_used = field(line, "pool_used")?;
                report.pool_capacity = field(line, "pool_capacity")?;
                report.framebuffer = field(line, "framebuffer")?;
                report.stack_peak = field(line, "stack_peak")?;
                memory = true;
            }
            Some("aa") => {
                let k: usize = line
                    .split_whitespace()
                    .nth(1)
                    .and_then(|k| k.parse().ok())
                    .ok_or_else(|| format!("no frame number in {line:?}"))?;
                if k != report.antialiasing.len() || k + 1 != report.frames.len() {
                    return Err(format!("{line:?} out of order"));
                }
                report.antialiasing.push(Antialiasing {
                    antialiased: field(line, "antialiased")? != 0,
                    pending_peak: field(line, "pending_peak")?,
                    pending_records: field(line, "pending_records")?,
                });
            }
            Some("composite") => {
                let k: usize = line
                    .split_whitespace()
                    .nth(1)
                    .and_then(|k| k.parse().ok())
                    .ok_or_else(|| format!("no frame number in {line:?}"))?;
                if k != report.composite.len() || k + 1 != report.frames.len() {
                    return Err(format!("{line:?} out of order"));
                }
                report.composite.push(CompositeUse {
                    fallback_rows: field(line, "fallback_rows")?,
                    composite_peak: field(line, "composite_peak")?,
                    composite_runs: field(line, "composite_runs")?,
                });
            }
            Some("gfx3d") => report.gfx3d_commands = Some(field(line, "commands_peak")?),
            Some("done") => done = true,
            _ => {}
        }
    }
    if report.variant.is_empty() || !memory || !done {
        return Err("the firmware's output stops before its `done` line".into());
    }
    Ok(report)
}

/// The median of `values` (the mean of the middle two for an even count, rounded down);
/// 0 for none.
pub fn median(values: &[u64]) -> u64 {
    let mut v = values.to_vec();
    v.sort_unstable();
    match v.len() {
        0 => 0,
        n if n % 2 == 1 => v[n / 2],
        n => (v[n / 2 - 1] + v[n / 2]) / 2,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const GOOD: &str = "peel-target variant=ftb-framebuffer target=thumbv7em-none-eabihf\n\
        frame 0 ticks=42079 display_bytes=153611 display_writes=2 fallback=0\n\
        frame 1 ticks=44539 display_bytes=153611 display_writes=2 fallback=1\n\
        memory pool_used=169440 pool_capacity=376832 framebuffer=153600 stack_peak=2596\n\
        done\n";

    #[test]
    fn parses_a_run() {
        let r = parse(GOOD).unwrap();
        assert_eq!(r.variant, "ftb-framebuffer");
        assert_eq!(r.target, "thumbv7em-none-eabihf");
        assert_eq!(r.frames.len(), 2);
        assert_eq!(
            r.frames[1],
            Frame {
                ticks: 44539,
                display_bytes: 153611,
                display_writes: 2,
                fallback: true
            }
        );
        assert_eq!(
            (r.pool_used, r.pool_capacity, r.framebuffer, r.stack_peak),
            (169440, 376832, 153600, 2596)
        );
        assert_eq!(r.gfx3d_commands, None);
        assert!(r.antialiasing.is_empty());
        let aa = GOOD
            .replace(
                "fallback=0\n",
                "fallback=0\naa 0 antialiased=1 pending_peak=80 pending_records=90\n",
            )
            .replace(
                "fallback=1\n",
                "fallback=1\naa 1 antialiased=0 pending_peak=90 pending_records=90\n",
            );
        let a = parse(&aa).unwrap().antialiasing;
        assert_eq!(
            a,
            [
                Antialiasing {
                    antialiased: true,
                    pending_peak: 80,
                    pending_records: 90
                },
                Antialiasing {
                    antialiased: false,
                    pending_peak: 90,
                    pending_records: 90
                }
            ]
        );
        let early = aa.replacen("aa 1", "aa 0", 1);
        assert!(parse(&early).unwrap_err().contains("out of order"));
        let transparent = GOOD
            .replace(
                "fallback=0\n",
                "fallback=0\ncomposite 0 fallback_rows=0 composite_peak=310 composite_runs=320\n",
            )
            .replace(
                "fallback=1\n",
                "fallback=1\ncomposite 1 fallback_rows=4 composite_peak=320 composite_runs=320\n",
            );
        let c = parse(&transparent).unwrap().composite;
        assert_eq!(
            c,
            [
                CompositeUse {
                    fallback_rows: 0,
                    composite_peak: 310,
                    composite_runs: 320
                },
                CompositeUse {
                    fallback_rows: 4,
                    composite_peak: 320,
                    composite_runs: 320
                }
            ]
        );
        assert!(
            parse(&transparent.replacen("composite 1", "composite 0", 1))
                .unwrap_err()
                .contains("out of order")
        );
        assert!(parse(GOOD).unwrap().composite.is_empty());
        let gfx = GOOD.replace("done", "gfx3d commands_peak=3184 capacity=16384\ndone");
        assert_eq!(parse(&gfx).unwrap().gfx3d_commands, Some(3184));
    }

    #[test]
    fn refuses_failures_and_truncation() {
        let failed = GOOD.replace(
            "done\n",
            "error: stack overflow: the stack reached the statics\n",
        );
        assert!(parse(&failed).unwrap_err().contains("stack overflow"));
        let cut = &GOOD[..GOOD.find("memory").unwrap()];
        assert!(parse(cut).unwrap_err().contains("done"));
        let skipped = GOOD.replace("frame 0 ", "frame 5 ");
        assert!(parse(&skipped).unwrap_err().contains("frame 5"));
        let garbled = GOOD.replace("ticks=42079", "ticks=x");
        assert!(parse(&garbled).unwrap_err().contains("ticks"));
    }

    #[test]
    fn medians() {
        assert_eq!(median(&[]), 0);
        assert_eq!(median(&[5, 1, 3]), 3);
        assert_eq!(median(&[4, 1, 3, 10]), 3);
    }
}
