//! The compiler's hash maps (exact geometry keys, mesh edges, palettes, bounds). The standard
//! SipHash is built to resist adversarial keys, which a compiler of its own user's scenes does
//! not need, and it dominated the output pass; foldhash with a fixed seed is several times
//! faster on these keys. Nothing depends on iteration order, so output stays deterministic.
//!
//! It also holds the parallel matching of exact keys ([`first_equal`]): keys are spread over
//! shards by a cheap hash of their integer words, and each shard is searched in index order,
//! so the result does not depend on the thread count.

use std::collections::{HashMap, HashSet};
use std::hash::Hash;

use rayon::prelude::*;

/// The hasher state of [`FastMap`] and [`FastSet`] (fixed seed: the same on every run).
pub type FastState = foldhash::fast::FixedState;

/// A `HashMap` with [`FastState`].
pub type FastMap<K, V> = HashMap<K, V, FastState>;

/// A `HashSet` with [`FastState`].
pub type FastSet<K> = HashSet<K, FastState>;

/// Hash shards of [`first_equal`] and of the output's line matching (parallel work units).
pub(crate) const SHARDS: usize = 64;

/// A cheap hash of exact keys, from their integer words. Equal keys have equal words, so equal
/// hashes; the hash only spreads keys over shards and map buckets (equality decides), and the
/// output does not depend on it.
pub(crate) trait ShardHash {
    /// The hash.
    fn shard_hash(&self) -> u64;
}

/// Mix 64-bit words (a multiply-rotate chain: every word reaches the low bits the shard uses).
pub(crate) fn mix(words: impl IntoIterator<Item = u64>) -> u64 {
    words.into_iter().fold(0x243F_6A88_85A3_08D3, |h, w| {
        (h ^ w).wrapping_mul(0x9E37_79B9_7F4A_7C15).rotate_left(29)
    })
}

/// A key with its hash, computed once: it picks the shard and serves the shard's map.
pub(crate) struct Hashed<'k, K> {
    /// The key's [`ShardHash::shard_hash`].
    pub hash: u64,
    /// The key.
    pub key: &'k K,
}

impl<K> Hash for Hashed<'_, K> {
    fn hash<H: std::hash::Hasher>(&self, state: &mut H) {
        state.write_u64(self.hash);
    }
}

impl<K: Eq> PartialEq for Hashed<'_, K> {
    fn eq(&self, other: &Self) -> bool {
        self.hash == other.hash && self.key == other.key
    }
}

impl<K: Eq> Eq for Hashed<'_, K> {}

/// The shard of a hash (see [`SHARDS`]).
pub(crate) fn shard(hash: u64) -> usize {
    (hash % SHARDS as u64) as usize
}

/// For each of `keys`, the index of the first key equal to it. Keys are bucketed by hash
/// and each bucket is searched in parallel, in index order.
pub(crate) fn first_equal<K: ShardHash + Eq + Sync>(keys: &[K]) -> Vec<u32> {
    let hashes: Vec<u64> = keys.par_iter().map(ShardHash::shard_hash).collect();
    let mut buckets: Vec<Vec<u32>> = vec![Vec::new(); SHARDS];
    for (i, &h) in hashes.iter().enumerate() {
        buckets[shard(h)].push(i as u32);
    }
    let firsts: Vec<Vec<(u32, u32)>> = buckets
        .into_par_iter()
        .map(|bucket| {
            let mut first: FastMap<Hashed<'_, K>, u32> = FastMap::default();
            bucket
                .into_iter()
                .map(|i| {
                    let key = Hashed {
                        hash: hashes[i as usize],
                        key: &keys[i as usize],
                    };
                    (i, *first.entry(key).or_insert(i))
                })
                .collect()
        })
        .collect();
    let mut out = vec![0; keys.len()];
    for (i, f) in firsts.into_iter().flatten() {
        out[i as usize] = f;
    }
    out
}

#[cfg(test)]
mod tests {
    use proptest::prelude::*;

    use super::*;

    impl ShardHash for u8 {
        fn shard_hash(&self) -> u64 {
            mix([u64::from(*self)])
        }
    }

    proptest! {
        /// The parallel, hash-sharded matching gives, for each key, the index of its first
        /// equal key, as a plain scan does.
        #[test]
        fn first_equal_finds_the_first_equal_key(keys in proptest::collection::vec(0u8..20, 0..400)) {
            let want: Vec<u32> = keys
                .iter()
                .map(|k| keys.iter().position(|j| j == k).unwrap_or(0) as u32)
                .collect();
            prop_assert_eq!(first_equal(&keys), want);
        }
    }
}
