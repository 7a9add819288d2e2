//! The compiler's hash maps (exact geometry keys, mesh edges, palettes, bounds). The standard
//! SipHash is built to resist adversarial keys, which a compiler of its own user's scenes does
//! not need, and it dominated the output pass; foldhash with a fixed seed is several times
//! faster on these keys. Nothing depends on iteration order, so output stays deterministic.

use std::collections::{HashMap, HashSet};

/// The hasher state of [`FastMap`] and [`FastSet`] (fixed seed: the same on every run).
pub type FastState = foldhash::fast::FixedState;

/// A `HashMap` with [`FastState`].
pub type FastMap<K, V> = HashMap<K, V, FastState>;

/// A `HashSet` with [`FastState`].
pub type FastSet<K> = HashSet<K, FastState>;
