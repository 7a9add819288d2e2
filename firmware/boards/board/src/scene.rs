//! The scene a board's build script compiled, brought into the board's `main.rs`.

/// Declares, in the board crate, what its build script (`board-build.rs`) wrote to `OUT_DIR`:
///
/// * `SCENE`, the `.peel` file: an array of its own, so that its symbol's size in the ELF is
///   the scene's flash (`.ci/board-size` prints it);
/// * `mod scene`, the scene's sizes file (`STACK`, `VERTS`, `SCAN_NODES`, ...);
/// * `type Memory`, the [`Memory`](crate::Memory) those sizes ask for: plain, or with the
///   feature `antialias` the anti-aliased figures (`SCAN_NODES_AA`, `PENDING_PIXELS`);
/// * `type Firmware`, the [`Firmware`](crate::Firmware) of that scene and memory.
#[macro_export]
macro_rules! include_scene {
    () => {
        /// The scene, compiled by build.rs.
        static SCENE: [u8; scene::BYTES] = *include_bytes!(concat!(env!("OUT_DIR"), "/scene.peel"));

        /// The scene's sizes, written beside it by build.rs.
        mod scene {
            include!(concat!(env!("OUT_DIR"), "/scene.rs"));
        }

        /// The frame memory the scene needs, sized by its sizes file.
        type Memory = $crate::Memory<
            { scene::STACK },
            { scene::VERTS },
            { $crate::scan_nodes(scene::SCAN_NODES, scene::SCAN_NODES_AA) },
            { $crate::vertex_memory(scene::VERTEX_MEMORY) },
            { $crate::pending_records(scene::PENDING_PIXELS) },
        >;

        /// The scene and its memory, as `main` hands them to the board's set-up.
        type Firmware = $crate::Firmware<'static, Memory>;
    };
}

/// A board's `main`: the scene ([`include_scene!`]), then an entry point (`$entry`, the board
/// HAL's or `cortex_m_rt::entry`) that takes the board's static memory, zeros in `.bss` (the
/// frame [`Memory`](crate::Memory) and mipidsi's transfer buffer, whose length is the burst
/// in which pixels go out), and hands it with the scene to `$hardware`, the board's function
/// that sets up its clocks, pins and SPI and calls [`Firmware::start`](crate::Firmware::start).
#[macro_export]
macro_rules! main {
    ($entry:path, $hardware:ident) => {
        $crate::include_scene!();

        #[$entry]
        fn main() -> ! {
            // cortex-m-rt turns these `static mut` into `&'static mut` owned by `main`.
            static mut MEMORY: Memory = Memory::new();
            static mut SPI_BUFFER: [u8; 512] = [0; 512];
            $hardware($crate::Firmware::new(&SCENE, MEMORY), SPI_BUFFER)
        }
    };
}
