//! What every binary's command line shares: whole-number flags that say their range when
//! the value is wrong (negative, a fraction, `1e9`, NaN), and one exit status (1) for every
//! refused command line, whatever refused it.

/// A clap value parser for a whole number in `lo..=hi`: written as digits (with a sign) or
/// as a whole number in exponent form (`1e3`). Anything else, or a value outside the
/// range, is refused with the accepted range (`unit` follows the upper bound, as in
/// `" per frame"`).
pub fn whole_in<T>(
    lo: i64,
    hi: i64,
    unit: &'static str,
) -> impl Fn(&str) -> Result<T, String> + Clone + Send + Sync + 'static
where
    T: TryFrom<i64> + Clone + Send + Sync + 'static,
{
    move |s: &str| {
        let refuse = || format!("must be a whole number between {lo} and {hi}{unit}");
        let v = parse_whole(s).ok_or_else(refuse)?;
        if v < lo || v > hi {
            return Err(refuse());
        }
        T::try_from(v).map_err(|_| refuse())
    }
}

/// `s` as a whole number: an integer, or a float with no fraction within i64's range.
fn parse_whole(s: &str) -> Option<i64> {
    let s = s.trim();
    if let Ok(v) = s.parse::<i64>() {
        return Some(v);
    }
    let f = s.parse::<f64>().ok()?;
    // 2^63 is exact as a float; anything at or past it does not fit in an i64.
    const LIMIT: f64 = (1u64 << 63) as f64;
    (f.is_finite() && f.fract() == 0.0 && f.abs() < LIMIT).then_some(f as i64)
}

/// Parses the command line; help and version print and exit 0, and anything refused
/// prints clap's message (naming the flag and, for numbers, the accepted range) and exits
/// with status 1, as every other error of these binaries does.
pub fn parse<P: clap::Parser>() -> P {
    match P::try_parse() {
        Ok(p) => p,
        Err(e) => exit_on(e),
    }
}

fn exit_on(e: clap::Error) -> ! {
    use clap::error::ErrorKind;
    match e.kind() {
        ErrorKind::DisplayHelp | ErrorKind::DisplayVersion => e.exit(),
        _ => {
            let _ = e.print();
            std::process::exit(1)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn whole_numbers_in_range_are_taken_in_any_whole_form() {
        let p = whole_in::<usize>(1, 1999, " cells a side");
        assert_eq!(p("64"), Ok(64));
        assert_eq!(p(" 128 "), Ok(128));
        assert_eq!(p("1e3"), Ok(1000));
        assert_eq!(p("1999"), Ok(1999));
        assert_eq!(p("1"), Ok(1));
    }

    #[test]
    fn anything_else_is_refused_with_the_range() {
        let p = whole_in::<usize>(1, 1999, " cells a side");
        let msg = "must be a whole number between 1 and 1999 cells a side";
        for bad in [
            "0",
            "2000",
            "-3",
            "1e9",
            "1.5",
            "nan",
            "inf",
            "-inf",
            "",
            "abc",
            "1e400",
            "99999999999999999999999",
        ] {
            assert_eq!(p(bad), Err(msg.to_string()), "{bad:?}");
        }
        let u = whole_in::<u32>(1, 99, "");
        assert_eq!(
            u("-1"),
            Err("must be a whole number between 1 and 99".into())
        );
        assert_eq!(u("80"), Ok(80));
    }
}
