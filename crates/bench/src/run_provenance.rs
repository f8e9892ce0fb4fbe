//! Where a bench run comes from, for the results files committed under docs/results/: the
//! command as typed, the commit of the source and the day. Invariant: nothing recorded names
//! a path of the machine the run was made on (the output folder is written `<out>`, the
//! program as `aograph`).

use std::process::Command;
use std::time::{SystemTime, UNIX_EPOCH};

/// The command line `args` (the program first) as a user would type it: `aograph`, then the
/// arguments, the value of `--out` (or `--out=...`) replaced by `<out>`.
pub fn command_line(args: impl IntoIterator<Item = String>) -> String {
    let mut out = vec!["aograph".to_string()];
    let mut hide_next = false;
    for arg in args.into_iter().skip(1) {
        if hide_next {
            out.push("<out>".into());
            hide_next = false;
        } else if arg == "--out" {
            out.push(arg);
            hide_next = true;
        } else if arg.starts_with("--out=") {
            out.push("--out=<out>".into());
        } else {
            out.push(arg);
        }
    }
    out.join(" ")
}

/// The checkout's commit, `+dirty` when files differ from it; `None` outside a git checkout.
pub fn commit() -> Option<String> {
    let git = |args: &[&str]| {
        let o = Command::new("git").args(args).output().ok()?;
        o.status
            .success()
            .then(|| String::from_utf8_lossy(&o.stdout).trim().to_string())
    };
    let head = git(&["rev-parse", "--short", "HEAD"])?;
    let dirty =
        git(&["status", "--porcelain", "--untracked-files=no"]).is_some_and(|s| !s.is_empty());
    Some(if dirty { format!("{head}+dirty") } else { head })
}

/// Today's date, UTC, YYYY-MM-DD.
pub fn today() -> String {
    let days = SystemTime::now()
        .duration_since(UNIX_EPOCH)
        .map_or(0, |d| d.as_secs() / 86_400) as i64;
    let (y, m, d) = civil_from_days(days);
    format!("{y:04}-{m:02}-{d:02}")
}

/// The proleptic Gregorian date of day `days` since 1970-01-01 (Howard Hinnant's
/// `civil_from_days`).
fn civil_from_days(days: i64) -> (i64, u32, u32) {
    let z = days + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z.rem_euclid(146_097);
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let d = (doy - (153 * mp + 2) / 5 + 1) as u32;
    let m = if mp < 10 { mp + 3 } else { mp - 9 } as u32;
    let y = yoe + era * 400 + i64::from(m <= 2);
    (y, m, d)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn days_since_the_epoch_are_calendar_dates() {
        assert_eq!(civil_from_days(0), (1970, 1, 1));
        assert_eq!(civil_from_days(59), (1970, 3, 1));
        // 2000 was a leap year (divisible by 400), 2100 will not be.
        assert_eq!(civil_from_days(11_016), (2000, 2, 29));
        assert_eq!(civil_from_days(20_793), (2026, 12, 6));
        assert_eq!(civil_from_days(47_541), (2100, 3, 1));
    }

    #[test]
    fn the_output_folder_is_not_recorded() {
        let args = [
            "/home/me/aograph/target/release/aograph",
            "bench",
            "--out",
            "/tmp/x",
            "--scenes",
            "columns",
        ];
        assert_eq!(
            command_line(args.map(String::from)),
            "aograph bench --out <out> --scenes columns"
        );
        assert_eq!(
            command_line(["x", "bench", "--out=/tmp/y"].map(String::from)),
            "aograph bench --out=<out>"
        );
    }
}
