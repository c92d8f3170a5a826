//! Checks of a received [`PieceList`]'s lines and pins: the seams' outline edges, the
//! pattern's lines and the pinned vertices.

use super::{
    MAX_OUTLINE_SEGMENTS, MAX_PINS, MAX_SEAM_SEGMENTS, MAX_SEAM_STRETCH, OutlineSegment, PieceList,
    SeamSegment, listed_count, malformed, outline,
};
use crate::MessageError;

/// Checks a received list's seam segments and returns them: at most
/// [`MAX_SEAM_SEGMENTS`], each of a listed seam and stretch, with finite ends.
pub fn check_seam_segments(l: &PieceList) -> Result<Vec<SeamSegment>, MessageError> {
    let n = l.segment_count as usize;
    if n > MAX_SEAM_SEGMENTS {
        return Err(malformed(
            "piece list",
            format!("{n} seam segments (at most {MAX_SEAM_SEGMENTS})"),
        ));
    }
    let segments = &l.segments[..n];
    if let Some(k) = segments.iter().position(|g| {
        g.seam >= l.seam_count
            || g.stretch > MAX_SEAM_STRETCH
            || !g.a.iter().chain(&g.b).all(|c| c.is_finite())
    }) {
        return Err(malformed(
            "piece list",
            format!("seam segment {k} names no listed seam or stretch, or is not finite"),
        ));
    }
    Ok(segments.to_vec())
}

/// Checks a received list's pattern lines and returns them: at most
/// [`MAX_OUTLINE_SEGMENTS`], each of a listed piece (or none), of a known kind, with
/// finite ends.
pub fn check_outline(l: &PieceList) -> Result<Vec<OutlineSegment>, MessageError> {
    let n = listed_count(
        l.outline_count,
        l.outline_total,
        MAX_OUTLINE_SEGMENTS,
        "outline segments",
    )?;
    let lines = &l.outline[..n];
    if let Some(k) = lines.iter().position(|g| {
        (g.piece >= l.count && g.piece != u32::MAX)
            || g.kind > outline::LAST
            || !g.a.iter().chain(&g.b).all(|c| c.is_finite())
    }) {
        return Err(malformed(
            "piece list",
            format!(
                "outline segment {k} names no listed piece, is of no known kind or is not finite"
            ),
        ));
    }
    Ok(lines.to_vec())
}

/// Checks a received list's pins and returns them: at most [`MAX_PINS`], no more than
/// the total, in increasing order (so each once). A viewer still checks each against
/// its mesh: the list and the mesh travel apart.
pub fn check_pins(l: &PieceList) -> Result<Vec<u32>, MessageError> {
    let n = listed_count(l.pin_count, l.pin_total, MAX_PINS, "pins")?;
    let pins = &l.pins[..n];
    if let Some(k) = pins.windows(2).position(|w| w[0] >= w[1]) {
        return Err(malformed(
            "piece list",
            format!("pin {} is not past the one before it", k + 1),
        ));
    }
    Ok(pins.to_vec())
}
