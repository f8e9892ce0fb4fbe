//! The sizes an output may have: every side 1 to [`MAX_SIDE`] pixels. The CLI's config, the
//! renderer and its resizes check against the same bound.

use crate::error::{RenderError, RenderResult};

/// The largest output side, in pixels (wgpu's default 2D texture limit).
pub const MAX_SIDE: u32 = 8192;

/// `v` pixels as output side `name` ("width", "height"), or an error naming the range.
pub fn check_size(name: &str, v: u32) -> RenderResult<()> {
    if v == 0 || v > MAX_SIDE {
        return Err(RenderError::InvalidArgument {
            name: name.into(),
            value: v.to_string(),
            allowed: format!("1 to {MAX_SIDE} pixels"),
        });
    }
    Ok(())
}
