//! Camera frames: every way a header can disagree with its payload is one
//! error naming the field, and a frame crosses the frame service intact.

use iceoryx2::prelude::*;
use ipc_types::{FrameError, FrameHeader, PROTOCOL_VERSION};

#[test]
fn a_header_that_disagrees_with_its_payload_is_named() {
    let good = FrameHeader::mono8(640, 480);
    assert_eq!(good.check(640 * 480, 640, 480), Ok(()));
    let padded = FrameHeader { stride: 648, ..good };
    assert_eq!(padded.check(648 * 480, 640, 480), Ok(()));
    let cases = [
        (
            FrameHeader { protocol_version: 9, ..good },
            640 * 480,
            FrameError::WrongProtocolVersion { found: 9 },
        ),
        (FrameHeader { pixel_format: 3, ..good }, 640 * 480, FrameError::UnknownPixelFormat { found: 3 }),
        (FrameHeader { width: 0, ..good }, 0, FrameError::Empty { width: 0, height: 480 }),
        (
            FrameHeader { width: 1280, stride: 1280, ..good },
            1280 * 480,
            FrameError::TooLarge { width: 1280, height: 480, max_width: 640, max_height: 480 },
        ),
        (
            FrameHeader { stride: 600, ..good },
            600 * 480,
            FrameError::StrideTooSmall { stride: 600, width: 640 },
        ),
        (good, 640 * 479, FrameError::LengthMismatch { expected: 640 * 480, payload: 640 * 479 }),
        (
            FrameHeader { stride: u32::MAX, ..good },
            0,
            FrameError::LengthMismatch { expected: u32::MAX as u64 * 480, payload: 0 },
        ),
    ];
    for (h, len, want) in cases {
        let got = h.check(len, 640, 480);
        assert_eq!(got, Err(want), "{h:?}");
        let text = want.to_string();
        assert!(text.starts_with("camera_frame") && !text.contains('\n'), "{text}");
    }
    assert_eq!(good.protocol_version, PROTOCOL_VERSION);
}

#[test]
fn a_frame_crosses_the_frame_service_intact() {
    let prefix = ipc_types::rig_node::unique_prefix("upmt_frame");
    {
        let node = NodeBuilder::new()
            .config(&ipc_types::ports::config_with_prefix(&prefix).expect("prefix"))
            .signal_handling_mode(SignalHandlingMode::Disabled)
            .create::<ipc::Service>()
            .expect("node");
        let (w, h) = (64u32, 48u32);
        let publisher = ipc_types::ports::frame_publisher(&node, (w * h) as usize).expect("publisher");
        let subscriber = ipc_types::ports::frame_subscriber(&node).expect("subscriber");
        for seq in 1..=3u64 {
            let mut sample = publisher.loan_slice_uninit((w * h) as usize).expect("loan");
            *sample.user_header_mut() = FrameHeader { seq, stamp_ns: seq * 10, ..FrameHeader::mono8(w, h) };
            let sample = sample.write_from_fn(|i| (i as u64 * seq % 251) as u8);
            sample.send().expect("send");
        }
        let mut seen = 0;
        while let Some(s) = subscriber.receive().expect("receive") {
            let hdr = *s.user_header();
            assert_eq!(hdr.check(s.payload().len(), w, h), Ok(()));
            assert!(s.payload().iter().enumerate().all(|(i, &p)| p == (i as u64 * hdr.seq % 251) as u8));
            seen += 1;
            // Two frames are kept; the oldest was overwritten.
            assert_eq!(hdr.seq, seen + 1);
        }
        assert_eq!(seen, 2);
        // A loan larger than the publisher was made for fails, it does not grow.
        assert!(publisher.loan_slice_uninit((w * h + 1) as usize).is_err());
    }
    ipc_types::rig_node::remove_prefix_segment(&prefix);
}
