//! Greatest common divisors of the exact integers (canonical planes, vertex keys, line keys).
//!
//! Binary gcds that drop to a narrower type as soon as both operands fit, and a shortcut for a
//! running gcd that has become small (the usual case: the gcd of a point's or a plane's
//! coordinates has a few bits), where one remainder replaces hundreds of wide binary steps.

use ethnum::{I256, U256};

/// An unsigned word the binary gcd runs on.
trait Word:
    Copy
    + Ord
    + std::ops::Sub<Output = Self>
    + std::ops::BitOr<Output = Self>
    + std::ops::Shr<u32, Output = Self>
    + std::ops::Shl<u32, Output = Self>
{
    const ZERO: Self;
    const ONE: Self;
    fn trailing_zeros(self) -> u32;
    /// `gcd(a, b)` of two odd words `a <= b` in a narrower type, once `b` fits one.
    fn narrow(a: Self, b: Self) -> Option<Self>;
}

impl Word for u64 {
    const ZERO: u64 = 0;
    const ONE: u64 = 1;
    fn trailing_zeros(self) -> u32 {
        u64::trailing_zeros(self)
    }
    fn narrow(_: u64, _: u64) -> Option<u64> {
        None
    }
}

impl Word for u128 {
    const ZERO: u128 = 0;
    const ONE: u128 = 1;
    fn trailing_zeros(self) -> u32 {
        u128::trailing_zeros(self)
    }
    fn narrow(a: u128, b: u128) -> Option<u128> {
        let b = u64::try_from(b).ok()?;
        Some(u128::from(gcd_u64(a as u64, b)))
    }
}

impl Word for U256 {
    const ZERO: U256 = U256::ZERO;
    const ONE: U256 = U256::ONE;
    fn trailing_zeros(self) -> u32 {
        U256::trailing_zeros(self)
    }
    fn narrow(a: U256, b: U256) -> Option<U256> {
        (*b.high() == 0).then(|| U256::from(gcd_u128(a.as_u128(), b.as_u128())))
    }
}

/// Binary gcd (`gcd(0, b) = b`), handed to a narrower type as soon as both operands fit.
fn binary_gcd<W: Word>(mut a: W, mut b: W) -> W {
    if a == W::ZERO {
        return b;
    }
    if b == W::ZERO {
        return a;
    }
    // A running gcd that has reached 1 stays there (the binary steps would take one per bit).
    if a == W::ONE || b == W::ONE {
        return W::ONE;
    }
    let shift = (a | b).trailing_zeros();
    a = a >> a.trailing_zeros();
    loop {
        b = b >> b.trailing_zeros();
        if a > b {
            std::mem::swap(&mut a, &mut b);
        }
        // Both odd: their gcd is odd, and the shift restores the common powers of two.
        if let Some(g) = W::narrow(a, b) {
            return g << shift;
        }
        b = b - a;
        if b == W::ZERO {
            return a << shift;
        }
    }
}

/// `gcd(a, b)` (binary, `gcd(0, b) = b`).
pub(crate) fn gcd_u64(a: u64, b: u64) -> u64 {
    binary_gcd(a, b)
}

/// `gcd(a, b)` (binary, in 64 bits once both fit; one remainder first when only one does).
pub(crate) fn gcd_u128(a: u128, b: u128) -> u128 {
    match (u64::try_from(a), u64::try_from(b)) {
        (Ok(1), _) | (_, Ok(1)) => 1,
        (Ok(a64), Err(_)) if a64 != 0 => u128::from(gcd_u64(a64, (b % a) as u64)),
        (Err(_), Ok(b64)) if b64 != 0 => u128::from(gcd_u64((a % b) as u64, b64)),
        _ => binary_gcd(a, b),
    }
}

/// `gcd(a, b)` (binary, in 128 bits once both fit).
fn gcd_u256(a: U256, b: U256) -> U256 {
    binary_gcd(a, b)
}

/// `a mod m` for `0 < m < 2^64`, from the two 128-bit halves of `a`.
fn rem_small(a: U256, m: u64) -> u64 {
    let (hi, lo) = a.into_words();
    let m = u128::from(m);
    // hi·2^128 mod m, one 64-bit shift at a time (each product stays below 2^128).
    let h = ((((hi % m) << 64) % m) << 64) % m;
    ((h + lo % m) % m) as u64
}

/// `a / m` for `0 < m < 2^64`: long division by 64-bit limbs.
fn div_small(a: U256, m: u64) -> U256 {
    let (hi, lo) = a.into_words();
    let m = u128::from(m);
    let mut r = 0u128;
    let mut q = [0u128; 4];
    for (k, limb) in [
        hi >> 64,
        hi & u128::from(u64::MAX),
        lo >> 64,
        lo & u128::from(u64::MAX),
    ]
    .into_iter()
    .enumerate()
    {
        let cur = (r << 64) | limb;
        q[k] = cur / m;
        r = cur % m;
    }
    U256::from_words((q[0] << 64) | q[1], (q[2] << 64) | q[3])
}

/// `gcd(a, b)`: one remainder when `a` is small (a running gcd soon is), else binary.
pub(crate) fn gcd_wide(a: U256, b: U256) -> U256 {
    match u64::try_from(a) {
        Ok(1) => U256::ONE,
        Ok(m) if m != 0 => U256::from(gcd_u64(m, rem_small(b, m))),
        _ => gcd_u256(a, b),
    }
}

/// `c / g` for a positive `g` that divides `c`, with a limb division when `g` is small.
pub(crate) fn div_exact(c: I256, g: U256) -> I256 {
    match u64::try_from(g) {
        Ok(1) => c,
        Ok(m) if m != 0 => {
            let q = div_small(c.unsigned_abs(), m).as_i256();
            if c < I256::ZERO {
                -q
            } else {
                q
            }
        }
        _ => c / g.as_i256(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use num_bigint::BigInt;
    use num_traits::Zero;
    use proptest::prelude::*;

    /// The oracle: Euclid on big integers.
    fn gcd_big(mut a: BigInt, mut b: BigInt) -> BigInt {
        while !b.is_zero() {
            (a, b) = (b.clone(), a % b);
        }
        a
    }

    fn big(v: U256) -> BigInt {
        v.to_string().parse().unwrap()
    }

    fn ibig(v: I256) -> BigInt {
        v.to_string().parse().unwrap()
    }

    /// A U256 with `bits` random low bits, times `2^shift` (shared powers of two).
    fn wide(words: (u128, u128), bits: u32, shift: u32) -> U256 {
        let v = U256::from_words(words.0, words.1);
        let v = if bits == 0 {
            U256::ZERO
        } else {
            v >> (256 - bits)
        };
        v.checked_shl(shift).unwrap_or(U256::ZERO) & (U256::MAX >> 1)
    }

    proptest! {
        #[test]
        fn gcds_match_the_bigint_gcd(
            a in any::<(u128, u128)>(), b in any::<(u128, u128)>(),
            abits in 0u32..=255, bbits in 0u32..=255, shift in 0u32..=80,
            common in any::<u64>(),
        ) {
            let (a, b) = (wide(a, abits, shift), wide(b, bbits, 0));
            // A shared factor, so that gcds are not all tiny.
            let c = U256::from(common | 1);
            let (a, b) = (a / c * c, b / c * c);
            let want = gcd_big(big(a), big(b));
            prop_assert_eq!(big(gcd_u256(a, b)), want.clone());
            prop_assert_eq!(big(gcd_wide(a, b)), want.clone());
            prop_assert_eq!(big(gcd_wide(b, a)), want);
            let (a128, b128) = (a.as_u128(), b.as_u128());
            prop_assert_eq!(
                BigInt::from(gcd_u128(a128, b128)),
                gcd_big(BigInt::from(a128), BigInt::from(b128))
            );
            let (a64, b64) = (a128 as u64, b128 as u64);
            prop_assert_eq!(BigInt::from(gcd_u64(a64, b64)), gcd_big(BigInt::from(a64), BigInt::from(b64)));
        }

        #[test]
        fn small_remainders_and_divisions_match_bigint(
            a in any::<(u128, u128)>(), m in 1u64.., negative in any::<bool>(),
        ) {
            let a = U256::from_words(a.0, a.1) >> 1;
            prop_assert_eq!(BigInt::from(rem_small(a, m)), big(a) % BigInt::from(m));
            let exact = a / U256::from(m) * U256::from(m);
            let c = if negative { -exact.as_i256() } else { exact.as_i256() };
            prop_assert_eq!(ibig(div_exact(c, U256::from(m))), ibig(c) / BigInt::from(m));
            prop_assert_eq!(big(div_small(a, m)), big(a) / BigInt::from(m));
        }
    }

    #[test]
    fn edge_cases() {
        assert_eq!(gcd_u64(0, 0), 0);
        assert_eq!(gcd_u128(0, 12), 12);
        assert_eq!(gcd_u256(U256::ZERO, U256::from(7u8)), U256::from(7u8));
        assert_eq!(gcd_wide(U256::ZERO, U256::from(9u8)), U256::from(9u8));
        assert_eq!(gcd_wide(U256::from(6u8), U256::ZERO), U256::from(6u8));
        assert_eq!(gcd_u128(1 << 100, 1 << 70), 1 << 70);
        let big_g: U256 = U256::ONE << 200u32;
        assert_eq!(
            div_exact(I256::from(-3) * big_g.as_i256(), big_g),
            I256::from(-3)
        );
        assert_eq!(div_exact(I256::from(-42), U256::ONE), I256::from(-42));
    }
}
