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
    // Open stitches follow the normals, as vertex indices.
    let hs = ClothFrameHeader { stitches: 1, ..h };
    let mut with = [0.0f32; 14];
    with[12..].copy_from_slice(&[1.0, 0.0]);
    check_frame(&hs, &with).unwrap();
    assert_eq!(shared::sim_to_ui::frame_stitches(&hs, &with), vec![[1, 0]]);
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
