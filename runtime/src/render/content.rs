//! What a frame draws: one scene (any [`Source`]) or a world with posed objects
//! ([`Posed`]). [`Content`] lets [`super::Renderer`]'s draws take either; a frame of one
//! scene compiles to the code it always had (the other arm is never built for it).

use super::Source;
use crate::place::Posed;

/// What a frame draws: implemented for every [`Source`] (a [`crate::read::Scene`]) and for
/// [`Posed`] (a world and objects with their poses); not meant to be implemented elsewhere.
pub trait Content {
    /// The scene type of a frame of one scene.
    type Part: Source + ?Sized;
    /// Which of the two this is.
    fn drawn(&self) -> Drawn<'_, Self::Part>;
}

/// One scene, or a world with posed objects ([`Content::drawn`]).
#[derive(Debug)]
pub enum Drawn<'c, T: ?Sized> {
    /// One scene.
    One(&'c T),
    /// A world with posed objects.
    Posed(&'c Posed<'c, 'c>),
}

impl<T: Source + ?Sized> Content for T {
    type Part = T;
    #[inline(always)]
    fn drawn(&self) -> Drawn<'_, T> {
        Drawn::One(self)
    }
}

impl<'a> Content for Posed<'_, 'a> {
    type Part = crate::read::Scene<'a>;
    #[inline(always)]
    fn drawn(&self) -> Drawn<'_, Self::Part> {
        Drawn::Posed(self)
    }
}
