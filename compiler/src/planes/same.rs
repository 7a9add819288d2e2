//! Exact point identity without gcds: equality by cross-multiplication, and a hash that is
//! the same for every scaling of a point's homogeneous coordinates.
//!
//! The output merges equal vertices. Reducing `(X, Y, Z, W)` to lowest terms first made one
//! canonical key per point, but a gcd of ~200-bit integers costs thousands of instructions per
//! cut point. Instead:
//! - the hash is `(X/W, Y/W, Z/W)` modulo the Mersenne prime `2^61 − 1` (the same residues for
//!   `(λX, λY, λZ, λW)`, and for a grid point and a cut point that lands on it); the inverses
//!   of the `W`s are taken together ([`residues`]), three products each;
//! - equality is exact ([`same_point`]): `X·W' = X'·W` per coordinate in 512-bit products.
//!
//! The hash only groups candidates; equality alone decides, so nothing is approximate.

use ethnum::{I256, U256};

use super::{HomPoint, Vertex};

/// The modulus: `2^61 − 1`, a prime, so every non-zero residue has an inverse.
const P: u64 = (1 << 61) - 1;

/// `x mod P` for `x < 2^122` (two folds: `2^61 ≡ 1`).
fn fold(x: u128) -> u64 {
    let r = (x & u128::from(P)) + (x >> 61); // < 2^62
    let r = (r & u128::from(P)) + (r >> 61); // <= P
    let r = r as u64;
    if r >= P {
        r - P
    } else {
        r
    }
}

fn mul(a: u64, b: u64) -> u64 {
    fold(u128::from(a) * u128::from(b))
}

fn pow(mut a: u64, mut e: u64) -> u64 {
    let mut r = 1;
    while e > 0 {
        if e & 1 == 1 {
            r = mul(r, a);
        }
        a = mul(a, a);
        e >>= 1;
    }
    r
}

/// `v mod P` (in `0..P`).
fn residue(v: I256) -> u64 {
    let (hi, lo) = v.unsigned_abs().into_words();
    // 2^64 ≡ 2^3 (mod P): limb `i` weighs 8^i.
    let r = [lo as u64, (lo >> 64) as u64, hi as u64, (hi >> 64) as u64]
        .iter()
        .rev()
        .fold(0, |acc, &limb| fold(u128::from(acc) * 8 + u128::from(limb)));
    if v < I256::ZERO && r != 0 {
        P - r
    } else {
        r
    }
}

/// The residues of each of `points` (`(x, y, z)` mod `P`), `None` for a cut point whose `W`
/// is a multiple of `P` (no inverse; practically never, and only a weaker hash). The `W`s of
/// the cut points are inverted together: one exponentiation for the whole list.
pub fn residues(points: &[&Vertex]) -> Vec<Option<[u64; 3]>> {
    let ws: Vec<u64> = points
        .iter()
        .map(|v| match v {
            Vertex::Int(_) => 1,
            Vertex::Hom(h) => residue(h.w),
        })
        .collect();
    // Prefix products of the non-zero residues, then one inverse walked back down.
    let mut prefix = Vec::with_capacity(ws.len());
    let mut acc = 1;
    for &w in &ws {
        prefix.push(acc);
        if w != 0 {
            acc = mul(acc, w);
        }
    }
    let mut inv = pow(acc, P - 2);
    let mut out = vec![None; points.len()];
    for i in (0..points.len()).rev() {
        let w = ws[i];
        if w == 0 {
            continue;
        }
        let inv_w = mul(inv, prefix[i]);
        inv = mul(inv, w);
        out[i] = Some(match points[i] {
            Vertex::Int(p) => p.map(|c| i64::from(c).rem_euclid(P as i64) as u64),
            Vertex::Hom(h) => h.xyz.map(|c| mul(residue(c), inv_w)),
        });
    }
    out
}

/// `|a|·|b|` as eight little-endian 64-bit limbs (exact: any product of two 256-bit magnitudes).
fn product(a: U256, b: U256) -> [u64; 8] {
    let limbs = |v: U256| {
        let (hi, lo) = v.into_words();
        [lo as u64, (lo >> 64) as u64, hi as u64, (hi >> 64) as u64]
    };
    let (a, b) = (limbs(a), limbs(b));
    let mut out = [0u64; 8];
    for i in 0..4 {
        let mut carry = 0u128;
        for j in 0..4 {
            // At most (2^64 − 1)^2 + 2(2^64 − 1) = 2^128 − 1.
            let t = u128::from(a[i]) * u128::from(b[j]) + u128::from(out[i + j]) + carry;
            out[i + j] = t as u64;
            carry = t >> 64;
        }
        out[i + 4] = carry as u64;
    }
    out
}

/// `x / w = x' / w'` for `w, w' > 0`, exactly.
fn same_ratio(x: I256, w: I256, x2: I256, w2: I256) -> bool {
    (x < I256::ZERO) == (x2 < I256::ZERO)
        && product(x.unsigned_abs(), w2.unsigned_abs())
            == product(x2.unsigned_abs(), w.unsigned_abs())
}

fn same_hom(a: &HomPoint, b: &HomPoint) -> bool {
    (0..3).all(|k| same_ratio(a.xyz[k], a.w, b.xyz[k], b.w))
}

/// Whether `a` and `b` are the same point, exactly (in any homogeneous scaling).
pub fn same_point(a: &Vertex, b: &Vertex) -> bool {
    match (a, b) {
        (Vertex::Int(p), Vertex::Int(q)) => p == q,
        // |p| < 2^31 and W < 2^168: the product fits I256.
        (Vertex::Int(p), Vertex::Hom(h)) | (Vertex::Hom(h), Vertex::Int(p)) => {
            (0..3).all(|k| h.xyz[k] == I256::from(p[k]) * h.w)
        }
        (Vertex::Hom(g), Vertex::Hom(h)) => std::sync::Arc::ptr_eq(g, h) || same_hom(g, h),
    }
}

#[cfg(test)]
mod tests {
    use std::sync::Arc;

    use num_bigint::BigInt;
    use num_rational::BigRational;
    use proptest::prelude::*;

    use super::*;

    fn big(v: I256) -> BigInt {
        v.to_string().parse().expect("decimal")
    }

    fn hom(xyz: [I256; 3], w: I256) -> Vertex {
        Vertex::Hom(Arc::new(HomPoint::new(xyz, w).expect("w != 0")))
    }

    /// A 200-bit-ish signed integer from four words.
    fn wide() -> impl Strategy<Value = I256> {
        (any::<i64>(), any::<u64>(), any::<u64>(), 0u32..140).prop_map(|(a, b, c, shift)| {
            let v = (I256::from(a) << 128) | (I256::from(b) << 64) | I256::from(c);
            v >> shift
        })
    }

    fn positive() -> impl Strategy<Value = I256> {
        wide().prop_map(|w| w.unsigned_abs().as_i256() >> 60 | I256::ONE)
    }

    proptest! {
        /// The 512-bit product is the true product.
        #[test]
        fn product_is_exact(a in wide(), b in wide()) {
            let limbs = product(a.unsigned_abs(), b.unsigned_abs());
            let got = limbs.iter().rev().fold(BigInt::from(0), |acc, &l| (acc << 64) + BigInt::from(l));
            let want = big(a) * big(b);
            prop_assert_eq!(got, if want < BigInt::from(0) { -want } else { want });
        }

        /// A point and any scaling of it are the same point with the same residues; a point
        /// moved by one unit in one coordinate, or mirrored in it, is not.
        #[test]
        fn scaling_keeps_identity(
            xyz in [wide(), wide(), wide()],
            w in positive(),
            k in 1i64..(1 << 40),
            moved in 0usize..3,
        ) {
            let a = hom(xyz, w);
            let l = I256::from(k);
            let b = hom(xyz.map(|c| c * l), w * l);
            let mut shifted = xyz;
            shifted[moved] += I256::ONE;
            let c = hom(shifted, w);
            prop_assert!(same_point(&a, &b));
            prop_assert!(!same_point(&a, &c));
            // The mirror image in one coordinate is another point unless that coordinate is 0.
            let mut mirrored = xyz;
            mirrored[moved] = -mirrored[moved];
            prop_assert_eq!(same_point(&a, &hom(mirrored, w)), xyz[moved] == I256::ZERO);
            let r = residues(&[&a, &b, &c]);
            prop_assert_eq!(r[0], r[1]);
            // Equality agrees with the rationals.
            let q = |v: &Vertex| match v {
                Vertex::Hom(h) => h.xyz.map(|c| BigRational::new(big(c), big(h.w))),
                Vertex::Int(p) => p.map(|c| BigRational::from_integer(c.into())),
            };
            prop_assert_eq!(same_point(&a, &c), q(&a) == q(&c));
        }

        /// A cut point that lands on a grid point is that grid point, residues included.
        #[test]
        fn cut_point_on_the_grid(p in [any::<i32>(), any::<i32>(), any::<i32>()], w in positive()) {
            let g = Vertex::Int(p);
            let h = hom(p.map(|c| I256::from(c) * w), w);
            prop_assert!(same_point(&g, &h) && same_point(&h, &g));
            let r = residues(&[&g, &h]);
            prop_assert_eq!(r[0], r[1]);
            let mut q = p;
            q[0] = q[0].wrapping_add(1);
            prop_assert!(!same_point(&Vertex::Int(q), &h));
        }
    }

    #[test]
    fn residues_modulo_the_prime() {
        assert_eq!(residue(I256::from(P)), 0);
        assert_eq!(residue(I256::from(P) + I256::from(5)), 5);
        assert_eq!(residue(I256::from(-1)), P - 1);
        // 2^64 = 8 mod P; 2^192 = 8^3.
        assert_eq!(residue(I256::ONE << 64), 8);
        assert_eq!(residue(I256::ONE << 192), 512);
        // A W that is a multiple of P has no inverse: no residues, and the others are kept.
        let a = hom([I256::from(3); 3], I256::from(P));
        let b = hom([I256::from(6); 3], I256::from(2));
        let r = residues(&[&a, &b]);
        assert_eq!(r[0], None);
        assert_eq!(r[1], Some([3, 3, 3]));
    }
}
