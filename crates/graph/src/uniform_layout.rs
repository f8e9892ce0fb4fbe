//! Typed uniform blocks: a `#[repr(C)]` struct whose field names and byte offsets are known
//! ([`UniformLayout`], written with [`uniform_layout!`](crate::uniform_layout)), declared on a
//! pass with `PassBuilder::uniform_struct`, and checked at compile against the WGSL struct
//! naga reflects, member by member: the same names at the same offsets, not only the same
//! total size.
//!
//! Invariant: in a block that compiles, every WGSL member that is not padding has a Rust field
//! of its name, offset and size, every Rust field that is not padding is a WGSL member at its own
//! offset, and WGSL padding lies inside Rust padding (members and fields named `pad*` or
//! `_pad*` are padding; one `[f32; 2]` of Rust padding may cover two WGSL pads).

use crate::shader::StructMember;

/// One field of a typed uniform block: its name and byte offset in the Rust struct.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct UniformField {
    /// The Rust field's name (the WGSL member's, unless it is padding).
    pub name: &'static str,
    /// Its byte offset (`core::mem::offset_of!`).
    pub offset: u32,
    /// Its size in bytes.
    pub size: u32,
}

/// The size of the field `field` selects (what [`uniform_layout!`](crate::uniform_layout)
/// records; the selector is never called).
#[doc(hidden)]
pub const fn field_size<T, F>(_field: fn(&T) -> &F) -> u32 {
    std::mem::size_of::<F>() as u32
}

/// A uniform block whose fields the graph can check against the shader's struct: implement it
/// with [`uniform_layout!`](crate::uniform_layout).
pub trait UniformLayout: bytemuck::Pod {
    /// Every field, in declaration order.
    const FIELDS: &'static [UniformField];
}

/// Implements [`UniformLayout`] for a `#[repr(C)]` struct from its field names:
/// `uniform_layout!(SsaoUniform { samples, _pad0, radius, kernel });` (every field, in order).
#[macro_export]
macro_rules! uniform_layout {
    ($ty:ty { $($field:ident),* $(,)? }) => {
        impl $crate::UniformLayout for $ty {
            const FIELDS: &'static [$crate::UniformField] = &[
                $($crate::UniformField {
                    name: stringify!($field),
                    offset: ::core::mem::offset_of!($ty, $field) as u32,
                    size: $crate::uniform_field_size(|s: &$ty| &s.$field),
                }),*
            ];
        }
    };
}

/// Padding is named `pad`, `_pad`, `pad0`, `_pad3`, ...: exactly, so a member such as
/// `padding_scale` is checked like any other.
fn is_padding(name: &str) -> bool {
    let rest = name.strip_prefix('_').unwrap_or(name);
    rest.strip_prefix("pad")
        .is_some_and(|digits| digits.chars().all(|c| c.is_ascii_digit()))
}

/// The first difference between the Rust `fields` and the WGSL `members` of one block, in
/// words, or `None` when they agree (module invariant).
pub fn uniform_layout_mismatch(
    fields: &[UniformField],
    members: &[StructMember],
) -> Option<String> {
    for m in members {
        // The Rust field whose bytes hold the member: the last one starting at or before it.
        let covering = fields
            .iter()
            .filter(|f| f.offset <= m.offset)
            .max_by_key(|f| f.offset);
        match covering {
            Some(f) if is_padding(&m.name) && is_padding(f.name) => {}
            Some(f) if f.offset == m.offset && is_padding(&m.name) => {}
            Some(f) if f.offset == m.offset && f.name == m.name && f.size != m.size => {
                return Some(format!(
                    "`{}` is {} bytes in Rust but {} in WGSL",
                    m.name, f.size, m.size
                ));
            }
            Some(f) if f.offset == m.offset && f.name == m.name => {}
            Some(f) if f.offset == m.offset => {
                return Some(format!(
                    "byte {} is `{}` in Rust but `{}` in WGSL",
                    m.offset, f.name, m.name
                ));
            }
            _ => {
                return Some(format!(
                    "the WGSL member `{}` at byte {} has no Rust field at that offset",
                    m.name, m.offset
                ));
            }
        }
    }
    for f in fields.iter().filter(|f| !is_padding(f.name)) {
        match members.iter().find(|m| m.name == f.name) {
            None => {
                return Some(format!(
                    "the Rust field `{}` (byte {}) is no member of the WGSL struct",
                    f.name, f.offset
                ));
            }
            Some(m) if m.offset != f.offset => {
                return Some(format!(
                    "`{}` is at byte {} in Rust but at byte {} in WGSL",
                    f.name, f.offset, m.offset
                ));
            }
            Some(_) => {}
        }
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    fn member(name: &str, offset: u32) -> StructMember {
        StructMember {
            name: name.into(),
            offset,
            size: 4,
        }
    }
    fn field(name: &'static str, offset: u32) -> UniformField {
        UniformField {
            name,
            offset,
            size: 4,
        }
    }

    #[test]
    fn the_same_names_at_the_same_offsets_agree_padding_covers_padding() {
        // One `_pad: [f32; 3]` in Rust where WGSL has three scalar pads.
        let wgsl = [
            member("radius", 0),
            member("pad0", 4),
            member("pad1", 8),
            member("pad2", 12),
            member("dir", 16),
        ];
        let rust = [field("radius", 0), field("_pad", 4), field("dir", 16)];
        assert_eq!(uniform_layout_mismatch(&rust, &wgsl), None);
        // A named member inside Rust padding is not set by Rust: refused.
        let wgsl = [member("radius", 0), member("bias", 8), member("dir", 16)];
        assert_eq!(
            uniform_layout_mismatch(&rust, &wgsl).as_deref(),
            Some("the WGSL member `bias` at byte 8 has no Rust field at that offset")
        );
    }

    #[test]
    fn swapped_fields_of_one_size_are_named() {
        // Same total size, same offsets: only the names tell.
        let wgsl = [member("radius", 0), member("bias", 4)];
        let rust = [field("bias", 0), field("radius", 4)];
        assert_eq!(
            uniform_layout_mismatch(&rust, &wgsl).as_deref(),
            Some("byte 0 is `bias` in Rust but `radius` in WGSL")
        );
    }

    #[test]
    fn a_missing_member_and_a_misplaced_field_are_named() {
        let wgsl = [member("radius", 0), member("dir", 16)];
        assert_eq!(
            uniform_layout_mismatch(&[field("radius", 0)], &wgsl).as_deref(),
            Some("the WGSL member `dir` at byte 16 has no Rust field at that offset")
        );
        let rust = [field("radius", 0), field("dir", 16), field("extra", 28)];
        assert_eq!(
            uniform_layout_mismatch(&rust, &wgsl).as_deref(),
            Some("the Rust field `extra` (byte 28) is no member of the WGSL struct")
        );
    }

    #[test]
    fn a_member_wider_in_wgsl_than_in_rust_is_named() {
        // Rust { dir: [f32; 3], _pad: f32 } against WGSL { dir: vec4<f32> }: the shader would
        // read dir.w from Rust's padding.
        let wgsl = [StructMember {
            name: "dir".into(),
            offset: 0,
            size: 16,
        }];
        let rust = [
            UniformField {
                name: "dir",
                offset: 0,
                size: 12,
            },
            field("_pad", 12),
        ];
        assert_eq!(
            uniform_layout_mismatch(&rust, &wgsl).as_deref(),
            Some("`dir` is 12 bytes in Rust but 16 in WGSL")
        );
        assert!(is_padding("_pad3") && is_padding("pad") && !is_padding("padding_scale"));
    }
}
