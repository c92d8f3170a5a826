//! The services between real iceoryx2 nodes: delivery, history for late subscribers,
//! domain isolation, and rejection of malformed or mismatched messages.

#![allow(clippy::unwrap_used)]

use shared::domain::Domain;
use shared::haptic_to_sim::DeviceSample;
use shared::ports;
use shared::sim_to_haptic::LocalModel;
use shared::{Checked, Header, MessageError, PROTOCOL_VERSION, services};

fn domain(test: &str) -> Domain {
    Domain::new(&format!("t{}-{test}", std::process::id())).unwrap()
}

fn sample(seq: &mut u64, x: f32) -> DeviceSample {
    DeviceSample {
        header: Header::next(seq),
        tick: *seq,
        position: [x, 0.5, 0.0],
        device_ok: 1,
        ..Default::default()
    }
}

#[test]
fn device_samples_reach_a_late_subscriber_and_stay_in_their_domain() {
    let (d, other) = (domain("a"), domain("b"));
    {
        let hn = services::node(&d, "haptic").unwrap();
        let publisher = ports::publisher(&hn, services::device).unwrap();
        let mut seq = 0;
        for k in 0..5 {
            publisher.send_copy(sample(&mut seq, k as f32)).unwrap();
        }
        // A subscriber that joins now gets the latest value (history 1).
        let sn = services::node(&d, "sim").unwrap();
        let sub = ports::subscriber(&sn, services::device, None).unwrap();
        use iceoryx2::port::update_connections::UpdateConnections;
        publisher.update_connections().unwrap();
        let got = sub.receive().unwrap().unwrap();
        got.check().unwrap();
        assert_eq!(got.header.seq, 5);
        assert_eq!(got.position[0], 4.0);
        assert!(got.header.sent_ns > 0 && got.header.sent_ns <= shared::monotonic_ns());
        // Another domain's subscriber sees nothing.
        let on = services::node(&other, "sim").unwrap();
        let osub = ports::subscriber(&on, services::device, None).unwrap();
        publisher.send_copy(sample(&mut seq, 9.0)).unwrap();
        assert!(osub.receive().unwrap().is_none());
        let next = sub.receive().unwrap().unwrap();
        assert_eq!(next.position[0], 9.0);
    }
    d.remove_leftovers();
    other.remove_leftovers();
}

#[test]
fn malformed_and_mismatched_messages_are_rejected_with_a_reason() {
    let mut seq = 0;
    let mut s = sample(&mut seq, 0.0);
    s.check().unwrap();
    s.position[1] = f32::NAN;
    let e = s.check().unwrap_err();
    assert!(e.to_string().contains("position"), "{e}");
    let mut s = sample(&mut seq, 0.0);
    s.header.protocol = PROTOCOL_VERSION + 1;
    assert_eq!(
        s.check(),
        Err(MessageError::Protocol {
            theirs: PROTOCOL_VERSION + 1
        })
    );
    let mut m = LocalModel {
        header: Header::next(&mut seq),
        plane_count: 17,
        ..Default::default()
    };
    assert!(m.check().unwrap_err().to_string().contains("17 planes"));
    m.plane_count = 1;
    m.planes[0] = [0.0, 2.0, 0.0, 0.0];
    assert!(m.check().unwrap_err().to_string().contains("unit"));
    m.planes[0] = [0.0, 1.0, 0.0, 0.3];
    m.check().unwrap();
    // The workspace: all zero is the default; otherwise a real scale and centre.
    m.workspace = [0.0, 0.9, 0.0, 16.0];
    m.check().unwrap();
    for bad in [
        [0.0, 0.9, 0.0, 0.0],
        [0.0, 0.9, 0.0, -1.0],
        [0.0, 0.9, 0.0, 1e-30],
        [0.0, 0.9, 0.0, 1e4],
        [f32::NAN, 0.9, 0.0, 16.0],
        [0.0, 0.9, 0.0, f32::INFINITY],
        [0.0, 2e4, 0.0, 16.0],
    ] {
        m.workspace = bad;
        assert!(
            m.check().unwrap_err().to_string().contains("workspace"),
            "{bad:?} passed"
        );
    }
}

/// The pen's workspace reaches the whole body at one scale, and is the default mapping
/// where the body fits in that.
#[test]
fn the_workspace_reaches_the_whole_body() {
    use shared::sim_to_haptic::{
        DEFAULT_WORKSPACE_CENTRE, DEFAULT_WORKSPACE_SCALE, TOUCH_HALF_EXTENT_M, workspace_covering,
    };
    let reach = |w: [f32; 4], p: [f32; 3]| {
        (0..3).all(|i| (p[i] - w[i]).abs() <= TOUCH_HALF_EXTENT_M[i] * w[3] + 1e-6)
    };
    // A body within the default box: the default mapping.
    let w = workspace_covering([-0.1, 0.4, -0.1], [0.1, 0.6, 0.1]);
    assert_eq!(
        w,
        [
            DEFAULT_WORKSPACE_CENTRE[0],
            DEFAULT_WORKSPACE_CENTRE[1],
            DEFAULT_WORKSPACE_CENTRE[2],
            DEFAULT_WORKSPACE_SCALE
        ]
    );
    // The mannequin (1.77 m tall): the default reached only y 0.3-0.9.
    let (lo, hi) = ([-0.25, 0.0, -0.15], [0.25, 1.77, 0.15]);
    let old = [0.0, 0.6, 0.0, DEFAULT_WORKSPACE_SCALE];
    assert!(
        !reach(old, [0.0, 1.45, 0.1]),
        "the shoulder was in reach before"
    );
    let w = workspace_covering(lo, hi);
    for p in [
        lo,
        hi,
        [0.0, 1.45, 0.1],
        [0.25, 0.0, -0.15],
        [0.0, 0.9, 0.0],
    ] {
        assert!(reach(w, p), "{p:?} out of {w:?}");
    }
    // ... and the cube scene's pen still reaches where it starts (0.6 m up).
    let w = workspace_covering([-0.2, 0.0, -0.2], [0.2, 0.4, 0.2]);
    assert!(
        reach(w, [0.0, 0.6, 0.0]) && reach(w, [0.2, 0.0, 0.2]),
        "{w:?}"
    );
    assert!(w[3] < 10.0, "{w:?}");
    // A body given as nothing (no vertices): the default.
    let w = workspace_covering([f32::INFINITY; 3], [f32::NEG_INFINITY; 3]);
    assert_eq!(w[3], DEFAULT_WORKSPACE_SCALE);
}

#[test]
fn a_service_with_a_different_message_type_is_a_clear_mismatch() {
    let d = domain("m");
    {
        let n = services::node(&d, "old").unwrap();
        // Someone created saiho/device with another payload type (an older build).
        let name: iceoryx2::prelude::ServiceName = services::DEVICE.try_into().unwrap();
        let _old = n
            .service_builder(&name)
            .publish_subscribe::<u64>()
            .history_size(1)
            .subscriber_max_buffer_size(1)
            .open_or_create()
            .unwrap();
        let e = services::device(&n).err().unwrap();
        assert!(e.to_string().contains("protocol mismatch"), "{e}");
    }
    d.remove_leftovers();
}

#[test]
fn cloth_frames_and_meshes_are_checked() {
    use shared::sim_to_ui::{ClothFrameHeader, MeshCorner, MeshHeader, check_frame, check_mesh};
    let mut seq = 0;
    let h = ClothFrameHeader {
        header: Header::next(&mut seq),
        vertices: 2,
        ..Default::default()
    };
    check_frame(&h, &[0.0; 12]).unwrap();
    assert!(
        check_frame(&h, &[0.0; 11])
            .unwrap_err()
            .to_string()
            .contains("11 floats")
    );
    let mut bad = [0.0f32; 12];
    bad[5] = f32::INFINITY;
    assert!(check_frame(&h, &bad).is_err());
    // Open stitches follow the normals: two vertex indices and the seam's place.
    let hs = ClothFrameHeader { stitches: 1, ..h };
    let mut with = [0.0f32; 15];
    with[12..].copy_from_slice(&[1.0, 0.0, 3.0]);
    check_frame(&hs, &with).unwrap();
    assert_eq!(
        shared::sim_to_ui::frame_stitches(&hs, &with),
        vec![[1, 0, 3]]
    );
    for seam in [-1.0, 0.5, f32::MAX] {
        let mut bad = with;
        bad[14] = seam;
        let e = check_frame(&hs, &bad).unwrap_err().to_string();
        assert!(e.contains("stitch seam"), "{seam}: {e}");
    }
    assert!(
        check_frame(&hs, &[0.0; 12])
            .unwrap_err()
            .to_string()
            .contains("1 stitches")
    );
    for v in [2.0, -1.0, 0.5] {
        with[13] = v;
        let e = check_frame(&hs, &with).unwrap_err().to_string();
        assert!(e.contains("stitch vertex"), "{v}: {e}");
    }
    let m = MeshHeader {
        header: Header::next(&mut seq),
        vertices: 3,
        triangles: 1,
        ..Default::default()
    };
    let c = |v| MeshCorner {
        vertex: v,
        u: 0.5,
        v: 0.5,
        pattern: [0.1, 0.2],
    };
    check_mesh(&m, &[c(0), c(1), c(2)]).unwrap();
    assert!(
        check_mesh(&m, &[c(0), c(1), c(3)])
            .unwrap_err()
            .to_string()
            .contains("vertex 3 of 3")
    );
    assert!(check_mesh(&m, &[c(0), c(1)]).is_err());
}

/// The files in /dev/shm that start with `prefix`, with their owner and mode.
fn shm_files(prefix: &str) -> Vec<(String, u32, u32)> {
    use std::os::unix::fs::MetadataExt;
    std::fs::read_dir("/dev/shm")
        .unwrap()
        .flatten()
        .filter_map(|e| {
            let n = e.file_name().to_string_lossy().into_owned();
            let m = std::fs::symlink_metadata(e.path()).ok()?;
            n.starts_with(prefix)
                .then_some((n, m.uid(), m.mode() & 0o777))
        })
        .collect()
}

/// A running domain's shared memory and directory are the user's alone, its management
/// segment included (iceoryx2 makes it 0666); the last node's release removes them all.
#[test]
fn a_domains_files_are_the_users_alone_and_a_clean_stop_removes_them() {
    use std::os::unix::fs::MetadataExt;
    let d = domain("modes");
    assert!(d.prefix().contains(&format!("_{}_", shared::paths::uid())));
    {
        let node = services::node(&d, "haptic").unwrap();
        let publisher = ports::publisher(&node, services::device).unwrap();
        publisher.send_copy(sample(&mut 0, 1.0)).unwrap();
        let files = shm_files(&d.prefix());
        assert!(
            files.iter().any(|f| f.0.ends_with("global_mgmt")),
            "{files:?}"
        );
        for (name, owner, mode) in &files {
            assert_eq!(*owner, shared::paths::uid(), "{name}");
            assert_eq!(*mode, 0o600, "{name} is {mode:o}");
        }
        let root = d.root_dir().unwrap();
        assert_eq!(std::fs::metadata(&root).unwrap().mode() & 0o777, 0o700);
        let all = root.parent().unwrap();
        assert_eq!(std::fs::metadata(all).unwrap().mode() & 0o777, 0o700);
        let runtime = shared::paths::runtime_dir().unwrap();
        assert_eq!(std::fs::metadata(&runtime).unwrap().mode() & 0o777, 0o700);
        // Another node is alive: nothing is removed.
        let other = services::node(&d, "sim").unwrap();
        drop(other);
        assert!(!services::release(&d), "the haptic node still runs");
        assert!(!shm_files(&d.prefix()).is_empty());
    }
    assert!(services::release(&d));
    assert_eq!(shm_files(&d.prefix()), vec![]);
    assert!(
        !shared::paths::runtime_dir()
            .unwrap()
            .join("iceoryx2")
            .join(d.name())
            .exists()
    );
}

/// Another user's file where the domain's shared memory goes is refused, never opened.
/// Only root can make a file of another user's, so elsewhere this checks nothing more
/// than that the user's own files pass.
#[test]
fn another_users_file_in_the_domains_place_is_refused() {
    let d = domain("squat");
    let squat = std::path::PathBuf::from("/dev/shm").join(format!("{}node.squat", d.prefix()));
    std::fs::write(&squat, b"").unwrap();
    let root = shared::paths::uid() == 0;
    if root {
        std::os::unix::fs::chown(&squat, Some(65534), None).unwrap();
    }
    let r = services::node(&d, "haptic");
    std::fs::remove_file(&squat).unwrap();
    if root {
        let Err(e) = r else {
            panic!("a squatted domain is refused")
        };
        let e = e.to_string();
        assert!(
            e.contains("belongs to user 65534") && e.contains("choose another --domain"),
            "{e}"
        );
    } else {
        r.unwrap();
    }
    d.remove_leftovers();
}
