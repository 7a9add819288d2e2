//! Compile the scene at build time, sized for the panel, and put `memory.x` where the linker
//! finds it: the build script every board crate shares (`../board-build.rs`, which says how
//! `PEEL_BOARD_MESH` chooses the mesh).

include!("../board-build.rs");
