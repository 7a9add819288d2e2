//! The loader's non-fatal findings: each kind tallied (how many, and the first line) while
//! the faces are read, then worded as a few warnings, so a bad file does not give one per face.

use std::collections::BTreeMap;
use std::path::Path;

use super::lines;

/// How often something happened and where first.
#[derive(Debug, Default, Clone, Copy)]
pub(super) struct Tally {
    count: usize,
    first_line: usize,
}

impl Tally {
    pub(super) fn add(&mut self, line: usize) {
        if self.count == 0 {
            self.first_line = line;
        }
        self.count += 1;
    }

    /// "1 face" or "3 faces" (with the given words).
    fn count(&self, singular: &str, plural: &str) -> String {
        match self.count {
            1 => format!("1 {singular}"),
            n => format!("{n} {plural}"),
        }
    }

    /// "line 7" or "first at line 7".
    fn at(&self) -> String {
        match self.count {
            1 => format!("line {}", self.first_line),
            _ => format!("first at line {}", self.first_line),
        }
    }
}

/// Non-fatal findings, collected per kind so a bad file gives a few readable warnings.
#[derive(Debug, Default)]
pub(super) struct Notes {
    /// Faces with no `usemtl` before them (cleared where that is meant).
    pub(super) no_material: Tally,
    /// Faces whose material no library defines, by the line check's material name index.
    pub(super) undefined: BTreeMap<u32, Tally>,
    /// Faces whose material has no usable `Kd`, by material id.
    pub(super) no_kd: BTreeMap<usize, Tally>,
    /// `f` lines with fewer than three corners.
    pub(super) short_faces: Tally,
    /// `l` statements.
    pub(super) polylines: Tally,
    /// Polygon faces that are not simple, by reason.
    pub(super) not_simple: BTreeMap<String, Tally>,
    /// Faces of a textured material without (finite) texture coordinates at every corner, by
    /// material id.
    pub(super) no_uvs: BTreeMap<usize, Tally>,
}

impl Notes {
    /// The warnings, one per kind (per material or reason where they differ), in a fixed order.
    pub(super) fn into_warnings(
        self,
        path: &Path,
        checked: &lines::Lines,
        materials: &[tobj::Material],
        out: &mut Vec<String>,
    ) {
        let file = path.display();
        let t = &self.no_material;
        if t.count > 0 {
            let [r, g, b] = super::DEFAULT_COLOUR;
            let (them, get) = if t.count == 1 {
                ("it", "it gets")
            } else {
                ("them", "they get")
            };
            out.push(format!(
                "{file}: {} no material (no `usemtl` before {them}, {}): {get} the default \
                 colour {r},{g},{b}; `peel compile --default-colour R,G,B` \
                 (`Builder::default_colour` in a build script) chooses another and silences \
                 this warning",
                t.count("face has", "faces have"),
                t.at(),
            ));
        }
        for (name, t) in &self.undefined {
            out.push(format!(
                "{file}: material `{}` is not defined in any material library; {} ({}) use the default colour",
                checked.material_names[*name as usize],
                t.count("face", "faces"),
                t.at()
            ));
        }
        for (id, t) in &self.no_kd {
            out.push(format!(
                "{file}: material `{}` has no usable diffuse colour (`Kd`); {} ({}) use the default colour",
                materials[*id].name,
                t.count("face", "faces"),
                t.at()
            ));
        }
        let t = &self.short_faces;
        if t.count > 0 {
            out.push(format!(
                "{file}: skipped {} with fewer than three corners ({})",
                t.count("face", "faces"),
                t.at()
            ));
        }
        let t = &self.polylines;
        if t.count > 0 {
            out.push(format!(
                "{file}: skipped {} (`l` is not a surface; {})",
                t.count("polyline", "polylines"),
                t.at()
            ));
        }
        for (id, t) in &self.no_uvs {
            out.push(format!(
                "{file}: material `{}` has a texture (`map_Kd`), but {} ({}) no texture \
                 coordinates (`vt`) at every corner: {} its colour alone",
                materials[*id].name,
                t.count("face gives", "faces give"),
                t.at(),
                if t.count == 1 {
                    "it shows"
                } else {
                    "they show"
                },
            ));
        }
        for (why, t) in &self.not_simple {
            out.push(format!(
                "{file}: {} not a simple polygon because {why} ({}); triangulated as a fan from the first corner",
                t.count("face is", "faces are"),
                t.at()
            ));
        }
    }
}
