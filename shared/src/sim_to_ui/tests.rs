//! Checks of the messages cloth-sim sends viewers.

use super::*;

/// Segments of listed seams with finite ends pass; one naming a seam past the list,
/// one not finite, or more than fit are refused.
#[test]
fn seam_segments_are_checked() {
    let mut l = PieceList {
        seam_total: 2,
        seam_count: 2,
        segment_count: 2,
        ..PieceList::default()
    };
    l.segments[0] = SeamSegment {
        seam: 0,
        a: [0.0, 0.1],
        b: [0.0, 0.2],
        stretch: 0,
    };
    l.segments[1] = SeamSegment {
        seam: 1,
        a: [0.5, 0.1],
        b: [0.5, 0.2],
        stretch: MAX_SEAM_STRETCH,
    };
    let segments = check_seam_segments(&l).unwrap();
    assert_eq!(segments.len(), 2);
    assert_eq!(segments[0].label("A"), "A");
    assert_eq!(segments[1].label("B"), "B99");
    let mut bad = l;
    bad.segments[1].seam = 2;
    assert!(check_seam_segments(&bad).is_err());
    let mut bad = l;
    bad.segments[1].stretch = MAX_SEAM_STRETCH + 1;
    assert!(check_seam_segments(&bad).is_err());
    let mut bad = l;
    bad.segments[0].b[1] = f32::NAN;
    assert!(check_seam_segments(&bad).is_err());
    let mut bad = l;
    bad.segment_count = MAX_SEAM_SEGMENTS as u32 + 1;
    assert!(check_seam_segments(&bad).is_err());
}

/// A seam whose counts hold (stalled within open within pairs, gaps finite) passes;
/// more stalled than open pairs, a gap that is not a distance, or a dart's press that
/// is no leg, is refused.
#[test]
fn seams_are_checked() {
    let mut l = PieceList {
        seam_total: 1,
        seam_count: 1,
        ..PieceList::default()
    };
    l.seams[0] = SeamEntry {
        label: *b"A\0\0\0",
        label_len: 1,
        pairs: 12,
        open: 3,
        lengths: [0.24, 0.24],
        stalled: 3,
        stalled_gap: [0.015, 0.041],
        ..SeamEntry::default()
    };
    assert_eq!(check_seams(&l).unwrap()[0].stalled, 3);
    let mut bad = l;
    bad.seams[0].stalled = 4;
    assert!(check_seams(&bad).is_err());
    let mut bad = l;
    bad.seams[0].stalled_gap[1] = f32::INFINITY;
    assert!(check_seams(&bad).is_err());
    let mut bad = l;
    bad.seams[0].stalled_gap[0] = -0.01;
    assert!(check_seams(&bad).is_err());
    // A dart pressed toward either leg passes; a press that is none of them does not.
    let mut dart = l;
    dart.seams[0].dart = super::dart::SECOND;
    assert_eq!(check_seams(&dart).unwrap()[0].dart, super::dart::SECOND);
    dart.seams[0].dart = 3;
    assert!(check_seams(&dart).is_err());
}

/// The pattern file a design was made from goes in whole up to the command's 240
/// bytes; a length past them or bytes that are not UTF-8 are refused.
#[test]
fn the_source_is_checked() {
    let mut l = PieceList::default();
    assert_eq!(check_source(&l).unwrap(), "");
    l.source_len = put_text(&mut l.source, "patterns/dress.svg");
    assert_eq!(check_source(&l).unwrap(), "patterns/dress.svg");
    let mut bad = l;
    bad.source_len = SOURCE_LEN as u32 + 1;
    assert!(check_source(&bad).is_err());
    let mut bad = l;
    bad.source[0] = 0xff;
    let e = check_source(&bad).unwrap_err().to_string();
    assert!(e.contains("pattern file"), "{e}");
}

/// The pen's last answer comes with the tool state: none before the first; an answer
/// other than 0 or 1, a message past its buffer or not UTF-8, or another protocol's
/// header is refused.
#[test]
fn the_pens_answer_is_checked() {
    let mut s = ToolState {
        header: Header::next(&mut 0),
        ..ToolState::default()
    };
    assert_eq!(check_tool_state(&s).unwrap(), None);
    s.pen_said = 3;
    s.pen_message_len = put_text(&mut s.pen_message, "Cut: 12 vertices split");
    assert_eq!(
        check_tool_state(&s).unwrap(),
        Some((false, "Cut: 12 vertices split".to_string()))
    );
    s.pen_ok = 1;
    assert!(check_tool_state(&s).unwrap().unwrap().0);
    let mut bad = s;
    bad.pen_ok = 2;
    assert!(
        check_tool_state(&bad)
            .unwrap_err()
            .to_string()
            .contains("answer")
    );
    let mut bad = s;
    bad.pen_message_len = PEN_MESSAGE_LEN as u32 + 1;
    assert!(check_tool_state(&bad).is_err());
    let mut bad = s;
    bad.pen_message[0] = 0xff;
    assert!(
        check_tool_state(&bad)
            .unwrap_err()
            .to_string()
            .contains("message")
    );
    let mut bad = s;
    bad.header.protocol += 1;
    assert!(check_tool_state(&bad).is_err());
}

/// Pins in increasing order up to the total pass; a count past the buffer or the
/// total, or a pin out of order (or twice), is refused.
#[test]
fn pins_are_checked() {
    let mut l = PieceList {
        pin_total: 5,
        pin_count: 3,
        ..PieceList::default()
    };
    l.pins[..3].copy_from_slice(&[4, 17, 900]);
    assert_eq!(check_pins(&l).unwrap(), vec![4, 17, 900]);
    assert!(check_pins(&PieceList::default()).unwrap().is_empty());
    let mut bad = l;
    bad.pins[2] = 17;
    let e = check_pins(&bad).unwrap_err().to_string();
    assert!(e.contains("pin 2"), "{e}");
    let mut bad = l;
    bad.pin_count = 6;
    assert!(check_pins(&bad).is_err());
    let mut bad = l;
    (bad.pin_total, bad.pin_count) = (MAX_PINS as u32 + 2, MAX_PINS as u32 + 1);
    assert!(check_pins(&bad).is_err());
}
