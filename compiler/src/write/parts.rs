//! A file of parts (format [`PARTS_VERSION`], `formats/peel.md`): an optional world and named
//! objects, each a complete tree file compiled in its own frame, behind a table by which the
//! renderer finds them. The layout's numbers are the runtime's
//! ([`peel_runtime::read::layout`]), so the writer and the reader cannot drift apart.

use peel_runtime::read::layout::{
    parts_offset, MAGIC, MAX_NAME, MAX_PARTS, PARTS_HEADER_SIZE, PARTS_VERSION, PART_ENTRY_SIZE,
};
use peel_runtime::read::Scene;

use crate::error::CompileError;

/// Trees start at multiples of this: the reader reads their `u32` fields in place.
const TREE_ALIGN: usize = size_of::<u32>();

/// Checks what the table of a file of parts requires of its parts, before anything is
/// compiled: 1 to [`MAX_PARTS`] parts (`world` counts as one), object names of 1 to
/// [`MAX_NAME`] bytes, all distinct.
pub fn check_parts(world: bool, names: &[&str]) -> Result<(), CompileError> {
    let parts = names.len() + usize::from(world);
    if parts == 0 || parts > MAX_PARTS as usize {
        return Err(CompileError::PartCount {
            parts,
            max: MAX_PARTS,
        });
    }
    for (k, name) in names.iter().enumerate() {
        let problem = if name.is_empty() {
            "an object needs a name (the world alone has none)".to_string()
        } else if name.len() > MAX_NAME as usize {
            format!(
                "{} bytes: an object's name has at most {MAX_NAME}",
                name.len()
            )
        } else if names[..k].contains(name) {
            "given twice: each object needs a name of its own".to_string()
        } else {
            continue;
        };
        return Err(CompileError::PartName {
            name: (*name).to_string(),
            problem,
        });
    }
    Ok(())
}

/// The bytes of a file of parts holding `world` (a tree file's bytes, part 0 when given) and
/// `objects` (name and tree file bytes each, in this order). Deterministic: the table, then
/// the names in part order, then each tree at the next multiple of 4 (zero padding).
pub fn parts_file(
    world: Option<&[u8]>,
    objects: &[(String, Vec<u8>)],
) -> Result<Vec<u8>, CompileError> {
    let names: Vec<&str> = objects.iter().map(|(n, _)| n.as_str()).collect();
    check_parts(world.is_some(), &names)?;
    let parts: Vec<(&str, &[u8])> = world
        .map(|w| ("", w))
        .into_iter()
        .chain(objects.iter().map(|(n, t)| (n.as_str(), t.as_slice())))
        .collect();
    let u32_of = |v: usize| {
        u32::try_from(v).map_err(|_| {
            CompileError::Encode(format!(
                "a file of parts of over {v} bytes: offsets are 32-bit"
            ))
        })
    };
    let mut out = Vec::new();
    out.extend_from_slice(&MAGIC);
    out.extend_from_slice(&PARTS_VERSION.to_le_bytes());
    debug_assert_eq!(out.len(), parts_offset::FLAGS);
    out.extend_from_slice(&0u16.to_le_bytes());
    out.extend_from_slice(&u32_of(parts.len())?.to_le_bytes());
    out.extend_from_slice(&u32::from(world.is_some()).to_le_bytes());
    debug_assert_eq!(out.len(), PARTS_HEADER_SIZE);
    let names_at = parts_offset::TABLE + parts.len() * PART_ENTRY_SIZE;
    let names_end = names_at + parts.iter().map(|(n, _)| n.len()).sum::<usize>();
    let mut name_at = names_at;
    let mut tree_at = names_end;
    for (name, tree) in &parts {
        tree_at = tree_at.next_multiple_of(TREE_ALIGN);
        for field in [tree_at, tree.len(), name_at, name.len()] {
            out.extend_from_slice(&u32_of(field)?.to_le_bytes());
        }
        name_at += name.len();
        tree_at += tree.len();
    }
    u32_of(tree_at)?;
    for (name, _) in &parts {
        out.extend_from_slice(name.as_bytes());
    }
    for (_, tree) in &parts {
        out.resize(out.len().next_multiple_of(TREE_ALIGN), 0);
        out.extend_from_slice(tree);
    }
    Ok(out)
}

/// One part of a file of parts.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Part<'a> {
    /// The object's name; empty for the world.
    pub name: &'a str,
    /// The part's tree file, valid for the runtime's reader.
    pub tree: &'a [u8],
}

/// Whether `bytes` start as a file of parts does (magic and version), rather than as a tree.
pub fn is_parts_file(bytes: &[u8]) -> bool {
    bytes.starts_with(&MAGIC)
        && bytes.get(MAGIC.len()..parts_offset::FLAGS) == Some(&PARTS_VERSION.to_le_bytes()[..])
}

/// The parts of a file of parts, in file order (the world first when it has one), each tree
/// checked by the runtime's reader: for `peel inspect`, the build cache and the tests, while
/// the runtime's own reader of this format is written.
///
/// # Errors
/// What is wrong, with the byte offset where it is known.
pub fn read_parts(bytes: &[u8]) -> Result<Vec<Part<'_>>, String> {
    if !is_parts_file(bytes) {
        return Err("not a file of parts (magic or version)".into());
    }
    let u32_at = |at: usize| -> Result<usize, String> {
        bytes
            .get(at..at + size_of::<u32>())
            .map(|b| u32::from_le_bytes([b[0], b[1], b[2], b[3]]) as usize)
            .ok_or_else(|| format!("truncated at byte {at}"))
    };
    let flags = bytes
        .get(parts_offset::FLAGS..parts_offset::COUNT)
        .ok_or_else(|| format!("truncated at byte {}", parts_offset::FLAGS))?;
    if flags != [0, 0] {
        return Err(format!("unknown flags at byte {}", parts_offset::FLAGS));
    }
    let count = u32_at(parts_offset::COUNT)?;
    if count == 0 || count > MAX_PARTS as usize {
        return Err(format!("{count} parts: a file holds 1 to {MAX_PARTS}"));
    }
    let world = match u32_at(parts_offset::WORLD)? {
        0 => false,
        1 => true,
        w => return Err(format!("world field {w} at byte {}", parts_offset::WORLD)),
    };
    let mut parts = Vec::with_capacity(count);
    for k in 0..count {
        let entry = parts_offset::TABLE + k * PART_ENTRY_SIZE;
        let field = |i: usize| u32_at(entry + i * size_of::<u32>());
        let (tree_at, tree_len, name_at, name_len) = (field(0)?, field(1)?, field(2)?, field(3)?);
        let slice = |at: usize, len: usize, what: &str| {
            at.checked_add(len)
                .and_then(|end| bytes.get(at..end))
                .ok_or_else(|| format!("part {k}: its {what} at byte {at} runs past the end"))
        };
        let name = std::str::from_utf8(slice(name_at, name_len, "name")?)
            .map_err(|_| format!("part {k}: its name is not UTF-8"))?;
        if tree_at % TREE_ALIGN != 0 {
            return Err(format!(
                "part {k}: its tree at byte {tree_at} is not at a multiple of {TREE_ALIGN}"
            ));
        }
        let tree = slice(tree_at, tree_len, "tree")?;
        let label = if name.is_empty() { "world" } else { name };
        Scene::parse(tree).map_err(|e| format!("part {k} ({label}): {e}"))?;
        parts.push(Part { name, tree });
    }
    let names: Vec<&str> = parts
        .iter()
        .skip(usize::from(world))
        .map(|p| p.name)
        .collect();
    if world && !parts[0].name.is_empty() {
        return Err("the world has a name".into());
    }
    check_parts(world, &names).map_err(|e| e.to_string())?;
    Ok(parts)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::compile::{compile_mesh, CompileOptions};
    use crate::tools::scenes;

    fn tree(mesh: &crate::load::Mesh) -> Vec<u8> {
        compile_mesh(mesh, &CompileOptions::default(), &|_| {})
            .unwrap()
            .1
    }

    fn field(bytes: &[u8], at: usize) -> usize {
        u32::from_le_bytes(bytes[at..at + 4].try_into().unwrap()) as usize
    }

    /// The header and each table entry as `formats/peel.md` gives them, the names packed
    /// after the table, each tree whole at a multiple of 4 after them.
    #[test]
    fn the_table_points_at_each_name_and_tree() {
        let world = tree(&scenes::box_grid(1));
        let objects = vec![
            ("torus".to_string(), tree(&scenes::torus(8, 4))),
            ("b".to_string(), tree(&scenes::soup(5, 0.3, 1))),
        ];
        let bytes = parts_file(Some(&world), &objects).unwrap();
        assert_eq!(bytes[..4], MAGIC);
        assert_eq!(u16::from_le_bytes([bytes[4], bytes[5]]), PARTS_VERSION);
        assert_eq!(bytes[parts_offset::FLAGS..parts_offset::COUNT], [0, 0]);
        assert_eq!(field(&bytes, parts_offset::COUNT), 3);
        assert_eq!(field(&bytes, parts_offset::WORLD), 1);
        let want = [("", &world), ("torus", &objects[0].1), ("b", &objects[1].1)];
        let names_at = parts_offset::TABLE + 3 * PART_ENTRY_SIZE;
        let mut name_at = names_at;
        let mut end = names_at + "torus".len() + "b".len();
        for (k, (name, tree)) in want.iter().enumerate() {
            let entry = parts_offset::TABLE + k * PART_ENTRY_SIZE;
            let (t, tl, n, nl) = (
                field(&bytes, entry),
                field(&bytes, entry + 4),
                field(&bytes, entry + 8),
                field(&bytes, entry + 12),
            );
            assert_eq!((n, nl), (name_at, name.len()), "part {k}");
            assert_eq!(&bytes[n..n + nl], name.as_bytes());
            assert_eq!(t % 4, 0, "part {k}");
            assert!(t >= end && t < end + 4, "part {k}: tree at {t}, end {end}");
            assert!(bytes[end..t].iter().all(|&b| b == 0), "padding of part {k}");
            assert_eq!(&bytes[t..t + tl], tree.as_slice(), "part {k}");
            name_at += nl;
            end = t + tl;
        }
        assert_eq!(end, bytes.len());
        let parts = read_parts(&bytes).unwrap();
        let read: Vec<(&str, &[u8])> = parts.iter().map(|p| (p.name, p.tree)).collect();
        let want: Vec<(&str, &[u8])> = want.iter().map(|(n, t)| (*n, t.as_slice())).collect();
        assert_eq!(read, want);
        assert_eq!(parts_file(Some(&world), &objects).unwrap(), bytes);
    }

    #[test]
    fn objects_alone_have_no_world() {
        let objects = vec![("only".to_string(), tree(&scenes::box_grid(1)))];
        let bytes = parts_file(None, &objects).unwrap();
        assert_eq!(field(&bytes, parts_offset::COUNT), 1);
        assert_eq!(field(&bytes, parts_offset::WORLD), 0);
        let parts = read_parts(&bytes).unwrap();
        assert_eq!(parts.len(), 1);
        assert_eq!(parts[0].name, "only");
        assert!(is_parts_file(&bytes) && !is_parts_file(&objects[0].1));
    }

    #[test]
    fn names_and_counts_the_table_cannot_hold_are_refused() {
        let t = tree(&scenes::box_grid(1));
        let named = |names: &[&str]| -> Vec<(String, Vec<u8>)> {
            names.iter().map(|n| (n.to_string(), t.clone())).collect()
        };
        let long = "x".repeat(MAX_NAME as usize + 1);
        let longest = "x".repeat(MAX_NAME as usize);
        for (names, says) in [
            (vec![""], "needs a name"),
            (vec![long.as_str()], "at most"),
            (vec!["a", "b", "a"], "given twice"),
        ] {
            let e = parts_file(Some(&t), &named(&names)).unwrap_err();
            assert!(matches!(e, CompileError::PartName { .. }), "{e:?}");
            assert!(e.to_string().contains(says), "{e}");
        }
        assert!(parts_file(None, &named(&[longest.as_str()])).is_ok());
        let e = parts_file(None, &[]).unwrap_err();
        assert!(
            matches!(e, CompileError::PartCount { parts: 0, .. }),
            "{e:?}"
        );
        let many: Vec<String> = (0..MAX_PARTS).map(|k| format!("o{k}")).collect();
        let many: Vec<&str> = many.iter().map(String::as_str).collect();
        assert!(parts_file(None, &named(&many)).is_ok());
        let e = parts_file(Some(&t), &named(&many)).unwrap_err();
        assert!(
            matches!(e, CompileError::PartCount { parts, .. } if parts == MAX_PARTS as usize + 1),
            "{e:?}"
        );
    }

    #[test]
    fn a_damaged_table_is_refused() {
        let t = tree(&scenes::box_grid(1));
        let bytes = parts_file(None, &[("a".to_string(), t)]).unwrap();
        let mut past = bytes.clone();
        let len_at = parts_offset::TABLE + 4;
        past[len_at..len_at + 4].copy_from_slice(&(bytes.len() as u32).to_le_bytes());
        assert!(read_parts(&past).unwrap_err().contains("past the end"));
        assert!(read_parts(&bytes[..bytes.len() - 1]).is_err());
    }
}
