//! Correctly rounded reading of decimal numbers (`[±]digits[.digits][(E|D)[±]digits]`)
//! by Clinger's exact fast path, the digits read eight bytes at a time: the
//! double nearest each decimal it accepts, the same as any correct parser
//! gives; it declines the rest, for a general parser to read. And the
//! writing of a number a user gave, back in a message ([`shortest`]), and of
//! a level as printed ([`level_text`]).

/// Powers of ten that are exact doubles.
const EXACT_POW10: [f64; 23] = [
    1e0, 1e1, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9, 1e10, 1e11, 1e12, 1e13, 1e14, 1e15, 1e16,
    1e17, 1e18, 1e19, 1e20, 1e21, 1e22,
];

/// The fast path of decimal parsing (Clinger 1990) for the samples' usual
/// form, `[±]digits[.digits][(E|D)[±]digits]`: when the digits make an
/// integer `m ≤ 2⁵³` and the decimal exponent `e` is within ±22, `m` and
/// `10^|e|` are exact doubles, so the one product or quotient `m·10^e` is
/// the correctly rounded value, the same double as any correct parser's.
/// `None` for any other token (more digits, a larger exponent, other
/// syntax), which then goes to Rust's parser.
pub fn exact_decimal(t: &[u8]) -> Option<f64> {
    decimal_prefix(t).and_then(|(value, len)| (len == t.len()).then_some(value))
}

/// [`exact_decimal`] of the longest start of `t` in its form, with that
/// start's length: the token's value if the token ends there (`None` where
/// [`exact_decimal`] declines the token, or the form ends early: a fifth
/// exponent digit).
///
/// The digits are read eight bytes at a time ([`digit_run`]); near the end
/// of the text, or where a run has eight digits or more, the token is read
/// byte by byte ([`decimal_prefix_bytewise`], the same function of the
/// token).
#[inline(always)]
pub fn decimal_prefix(t: &[u8]) -> Option<(f64, usize)> {
    let negative = t.first() == Some(&b'-');
    let mut i = usize::from(matches!(t.first(), Some(b'-' | b'+')));
    let bytewise = || decimal_prefix_bytewise(t);
    let Some((whole, whole_digits)) = digit_run(t, i) else {
        return bytewise();
    };
    i += whole_digits;
    let (mut m, mut digits, mut fraction) = (whole, whole_digits, 0);
    if t.get(i) == Some(&b'.') {
        let Some((part, part_digits)) = digit_run(t, i + 1) else {
            return bytewise();
        };
        i += 1 + part_digits;
        m = m * POW10_U64[part_digits] + part;
        digits += part_digits;
        fraction = part_digits as i32;
    }
    // A run of eight may go on; 17 digits or more may not fit the form.
    if whole_digits == 8 || fraction == 8 || digits > 16 {
        return bytewise();
    }
    if digits == 0 {
        return None;
    }
    with_exponent(t, i, m, fraction, negative)
}

/// The end of [`decimal_prefix`] from byte `i`, after the mantissa: the
/// integer `m` of its digits, `fraction` of them after the point. Reads an
/// optional exponent (at most four digits) and gives the value when `m` and
/// the decimal exponent make Clinger's exact case, with the prefix's length.
#[inline(always)]
fn with_exponent(
    t: &[u8],
    mut i: usize,
    m: u64,
    fraction: i32,
    negative: bool,
) -> Option<(f64, usize)> {
    let mut exponent = 0i32;
    if i < t.len() && matches!(t[i], b'E' | b'e' | b'D' | b'd') {
        i += 1;
        let sign = match t.get(i) {
            Some(b'-') => {
                i += 1;
                -1
            }
            Some(b'+') => {
                i += 1;
                1
            }
            _ => 1,
        };
        let start = i;
        while i < t.len() && t[i].is_ascii_digit() && i - start < 4 {
            exponent = 10 * exponent + i32::from(t[i] - b'0');
            i += 1;
        }
        if i == start {
            return None;
        }
        exponent *= sign;
    }
    let e = exponent - fraction;
    if m > 1 << 53 || !(-22..=22).contains(&e) {
        return None;
    }
    let magnitude = if e < 0 {
        m as f64 / EXACT_POW10[(-e) as usize]
    } else {
        m as f64 * EXACT_POW10[e as usize]
    };
    Some((if negative { -magnitude } else { magnitude }, i))
}

/// Powers of ten up to 10⁸, for appending a run of digits.
const POW10_U64: [u64; 9] = [
    1,
    10,
    100,
    1_000,
    10_000,
    100_000,
    1_000_000,
    10_000_000,
    100_000_000,
];

/// The ASCII digits that start `t[i..]`, at most eight: their value and
/// how many, read from one 8-byte word (`None` if fewer than eight bytes
/// are left). SWAR, as in fast_float's `parse_eight_digits_unrolled`
/// (Lemire, "Number parsing at a gigabyte per second", 2021).
#[inline(always)]
fn digit_run(t: &[u8], i: usize) -> Option<(u64, usize)> {
    let word = u64::from_le_bytes(t.get(i..i + 8)?.try_into().ok()?);
    // Each byte minus '0': 0–9 for a digit. A byte below '0' wraps to 0x80
    // or more, one above '9' gives 0x80 or more once 0x76 is added; what
    // wraps or carries only reaches the bytes after it, past the run.
    let d = word.wrapping_sub(0x3030_3030_3030_3030);
    let not_digit = (d | d.wrapping_add(0x7676_7676_7676_7676)) & 0x8080_8080_8080_8080;
    let n = (not_digit.trailing_zeros() / 8) as usize;
    if n == 0 {
        return Some((0, 0));
    }
    // The run in the top n bytes, zeros (leading zeros) below.
    let v = d << (8 * (8 - n));
    let v = v.wrapping_mul(10).wrapping_add(v >> 8);
    let v = ((v & 0x0000_00FF_0000_00FF).wrapping_mul(100 + (1_000_000 << 32)))
        .wrapping_add(((v >> 16) & 0x0000_00FF_0000_00FF).wrapping_mul(1 + (10_000 << 32)))
        >> 32;
    Some((v & 0xFFFF_FFFF, n))
}

/// [`decimal_prefix`] read byte by byte.
fn decimal_prefix_bytewise(t: &[u8]) -> Option<(f64, usize)> {
    let mut i = 0;
    let negative = match t.first() {
        Some(b'-') => {
            i = 1;
            true
        }
        Some(b'+') => {
            i = 1;
            false
        }
        _ => false,
    };
    let (mut m, mut digits, mut fraction) = (0u64, 0u32, 0i32);
    let mut point = false;
    while i < t.len() {
        match t[i] {
            d @ b'0'..=b'9' => {
                // 19 digits cannot overflow u64; more leave the fast path.
                if digits == 19 {
                    return None;
                }
                m = 10 * m + u64::from(d - b'0');
                // Leading zeros do not count towards the 19.
                digits += u32::from(m != 0);
                fraction += i32::from(point);
            }
            b'.' if !point => point = true,
            _ => break,
        }
        i += 1;
    }
    let mantissa_digits =
        i - usize::from(negative || t.first() == Some(&b'+')) - usize::from(point);
    if mantissa_digits == 0 {
        return None;
    }
    with_exponent(t, i, m, fraction, negative)
}

/// A number as a file writes it, Fortran's `1.0D-02` too: the fast path
/// first, else the general parser (which also reads `inf` and `NaN`: the
/// callers refuse what is not finite, each in its own words).
pub fn read_number(token: &str) -> Option<f64> {
    if let Some(v) = exact_decimal(token.as_bytes()) {
        return Some(v);
    }
    match token.bytes().any(|b| b == b'D' || b == b'd') {
        true => token.replace(['D', 'd'], "E").parse::<f64>().ok(),
        false => token.parse::<f64>().ok(),
    }
}

/// Whether a token holds a comma between two digits (`1,5E-04`, `0,01`):
/// a decimal comma, where the files' numbers take a point.
pub fn comma_between_digits(token: &str) -> bool {
    let b = token.as_bytes();
    (1..b.len().saturating_sub(1))
        .any(|i| b[i] == b',' && b[i - 1].is_ascii_digit() && b[i + 1].is_ascii_digit())
}

/// A number as a message echoes it: the shortest text that reads back to
/// it, in exponent form where the plain one would be long (`1e-300`, not
/// three hundred zeros; `5e20`), else plain (`0.001`, `2`, `0.7`).
pub fn shortest(x: f64) -> String {
    let a = x.abs();
    if a != 0.0 && a.is_finite() && !(1e-4..1e15).contains(&a) {
        format!("{x:e}")
    } else {
        format!("{x}")
    }
}

/// A level of an IM (or any quantity a message states) as printed: four significant digits, trailing zeros
/// dropped (0.05 g, 2 g, 48.31 cm/s, 300 cm/s).
pub fn level_text(v: f64) -> String {
    if v == 0.0 || !v.is_finite() {
        return format!("{v}");
    }
    if !(1e-3..1e7).contains(&v.abs()) {
        // Four significant digits in exponent form, not hundreds of zeros.
        let text = format!("{v:.3e}");
        let (mantissa, exp) = text.split_once('e').expect("exponent form");
        let mantissa = mantissa.trim_end_matches('0').trim_end_matches('.');
        return format!("{mantissa}e{exp}");
    }
    let decimals = (3 - v.abs().log10().floor() as i32).max(0) as usize;
    let text = format!("{v:.decimals$}");
    if text.contains('.') {
        text.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        text
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Rust's parser (correctly rounded) on a token, `D` read as `E`.
    fn reference(token: &str) -> Option<f64> {
        token.replace(['D', 'd'], "E").parse::<f64>().ok()
    }

    #[test]
    fn fast_path_gives_the_correctly_rounded_double_or_declines() {
        // Every sample of the bundled records, each the same double as
        // Rust's parser gives.
        let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("records");
        let (mut files, mut fast, mut all) = (0, 0usize, 0usize);
        let mut dirs = vec![root];
        while let Some(dir) = dirs.pop() {
            for entry in std::fs::read_dir(&dir).unwrap() {
                let path = entry.unwrap().path();
                if path.is_dir() {
                    dirs.push(path);
                } else if path.extension().is_some_and(|e| e == "AT2") {
                    files += 1;
                    let text = std::fs::read_to_string(&path).unwrap();
                    for token in text
                        .lines()
                        .skip(crate::at2::HEADER_LINES)
                        .flat_map(str::split_whitespace)
                    {
                        let want = reference(token).unwrap();
                        all += 1;
                        if let Some(v) = exact_decimal(token.as_bytes()) {
                            fast += 1;
                            assert_eq!(v.to_bits(), want.to_bits(), "{}: {token}", path.display());
                        }
                    }
                }
            }
        }
        assert!(files >= 44, "{files} AT2 files");
        // The records' samples (7 significant digits) all take the fast path.
        assert_eq!(fast, all, "samples that took the fast path");
        assert!(all > 700_000, "{all} samples");

        // Edges: the largest exact mantissa and power of ten, one past each
        // (declined), signs, zeros, the forms Rust accepts, and malformed
        // tokens (declined).
        let taken = [
            "9007199254740992",
            "-9007199254740992e-22",
            "1e22",
            "-0",
            "-0.0e0",
            "+.5",
            "5.",
            "1.5D-02",
            "1.5d+02",
            "0000000000000000000000001",
            "0.0000000000000000000001",
            "123456789012345e-3",
            ".1",
            "-.2483657E-03",
            "7E+000",
            "3e-0022",
        ];
        for t in taken {
            let v = exact_decimal(t.as_bytes()).unwrap_or_else(|| panic!("{t} declined"));
            assert_eq!(v.to_bits(), reference(t).unwrap().to_bits(), "{t}");
        }
        let declined = [
            "9007199254740993",
            "1234567890123456789e-3",
            "1e23",
            "1e-23",
            "12345678901234567890",
            "0.00000000000000000000001",
            "1e99999",
            "inf",
            "NaN",
        ];
        for t in declined {
            assert_eq!(exact_decimal(t.as_bytes()), None, "{t}");
        }
        let malformed = [
            "", ".", "-", "+", "e5", ".e5", "1e", "1e+", "1.2.3", "--1", "1e5x", "0x10", "1,0",
            "1e5.0", "1 ", "1d", "E", "+-1",
        ];
        for t in malformed {
            assert_eq!(exact_decimal(t.as_bytes()), None, "{t}");
        }

        // Random decimals (a fixed LCG): mantissas of 1 to 21 digits, the
        // point anywhere, exponents from −40 to 40.
        let mut state = 0x2545_f491_4f6c_dd1du64;
        let mut next = |n: u64| {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (state >> 33) % n
        };
        for _ in 0..200_000 {
            let digits = 1 + next(21) as usize;
            let mut t: String = (0..digits)
                .map(|_| char::from(b'0' + next(10) as u8))
                .collect();
            if next(2) == 0 {
                t.insert(next(digits as u64 + 1) as usize, '.');
            }
            if next(2) == 0 {
                t.insert(0, '-');
            }
            if next(3) > 0 {
                t += &format!(
                    "{}{}",
                    ["E", "e", "D"][next(3) as usize],
                    next(81) as i64 - 40
                );
            }
            let want = reference(&t).unwrap();
            if let Some(v) = exact_decimal(t.as_bytes()) {
                assert_eq!(v.to_bits(), want.to_bits(), "{t}");
            }
        }
    }

    /// The digits read eight bytes at a time give what reading them byte by
    /// byte gives, value and length, or decline alike: on random tokens
    /// whose runs of digits end at every place of a word (0 to 20 digits,
    /// leading zeros, a point anywhere), followed by every kind of byte
    /// (the neighbours of '0' and '9', a second point, an exponent, a
    /// separator, non-ASCII, the text's end).
    #[test]
    fn digits_read_eight_at_a_time_read_as_byte_by_byte() {
        let mut state = 0x9e37_79b9_7f4a_7c15u64;
        let mut next = |n: u64| {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (state >> 33) % n
        };
        let after: [&[u8]; 12] = [
            b"",
            b" ",
            b"\n",
            b",",
            b"/",
            b":",
            b".5",
            b"E-03  ",
            b"e+7",
            b"D1",
            b"\xc2\xa0",
            b"x",
        ];
        let (mut read, mut swar) = (0, 0);
        for _ in 0..300_000 {
            let mut t = Vec::new();
            match next(3) {
                0 => t.push(b'-'),
                1 => t.push(b'+'),
                _ => {}
            }
            let digits = next(21) as usize;
            let zeros = next(4) as usize;
            for k in 0..digits {
                t.push(if k < zeros {
                    b'0'
                } else {
                    b'0' + next(10) as u8
                });
            }
            if next(3) > 0 {
                let at = t.len() - next(digits as u64 + 1) as usize;
                t.insert(at, b'.');
            }
            t.extend_from_slice(after[next(after.len() as u64) as usize]);
            // Enough text after the token for a word, or not.
            t.extend(std::iter::repeat_n(b' ', next(10) as usize));
            let want = decimal_prefix_bytewise(&t).map(|(v, n)| (v.to_bits(), n));
            let got = decimal_prefix(&t).map(|(v, n)| (v.to_bits(), n));
            assert_eq!(got, want, "{:?}", String::from_utf8_lossy(&t));
            read += usize::from(want.is_some());
            swar += usize::from(digit_run(&t, 0).is_some_and(|(_, n)| n > 0));
        }
        // Both outcomes and both paths are exercised.
        assert!(
            read > 100_000 && swar > 50_000,
            "{read} read, {swar} by words"
        );
        // Runs of every length, by hand: 0 to 8 digits then a blank.
        for n in 0..=8 {
            let text = format!("{}{}", &"12345678"[..n], " ".repeat(8));
            let want = "12345678"[..n].parse::<u64>().unwrap_or(0);
            assert_eq!(digit_run(text.as_bytes(), 0), Some((want, n)), "{text:?}");
        }
        assert_eq!(digit_run(b"1234567", 0), None);
    }

    /// Echoed numbers read back to themselves, and are short at the
    /// extremes (by hand).
    #[test]
    fn shortest_echoes_read_back_and_stay_short() {
        for (x, text) in [
            (1e-300, "1e-300"),
            (5e20, "5e20"),
            (0.001, "0.001"),
            (2.0, "2"),
            (0.7, "0.7"),
            (-3.5e-7, "-3.5e-7"),
            (0.0, "0"),
            (f64::INFINITY, "inf"),
        ] {
            assert_eq!(shortest(x), text);
            assert_eq!(text.parse::<f64>().unwrap(), x);
        }
    }
}
