//! ethercrab's MainDevice against the simulated chain, in process: every
//! frame ethercrab sends is answered by `Chain::answer` on a transport
//! thread and fed back to it, as a NIC would. Start-up reaches OP (identity
//! and PDO mapping read from SII and CoE, SyncManagers and FMMUs written),
//! an SDO written in PRE-OP reaches the drive, and the CiA 402 drives are
//! switched on and follow their targets over cyclic process data with the
//! working counter an ESC gives (3 per drive). Faults as the wire shows
//! them: a cut cable lowers the working counter, a lost frame is a
//! timeout, a drive fault shows in its statusword and is reset through
//! the controlword, all without restarting anything.

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex};
use std::task::{Wake, Waker};
use std::thread;
use std::time::Duration;

use ethercat_sim::cia402::PowerState;
use ethercat_sim::subdevice::al_state;
use ethercat_sim::{Chain, FrameError, SubDevice};
use ethercrab::std::ethercat_now;
use ethercrab::{MainDevice, MainDeviceConfig, PduRx, PduStorage, PduTx, Timeouts};

const DRIVES: usize = 3;
/// Generous: the transport thread may wait for a CPU while the rest of the
/// test suite runs; only the injected lost frame should ever time out.
const PDU_TIMEOUT: Duration = Duration::from_millis(500);
static STORAGE: Storage = PduStorage::new();
static FAULT_STORAGE: Storage = PduStorage::new();

struct Unpark(thread::Thread);

impl Wake for Unpark {
    fn wake(self: Arc<Self>) {
        self.0.unpark();
    }
}

/// The "wire": each frame ethercrab sends goes through `chain` and back.
fn transport(
    mut tx: PduTx<'static>,
    mut rx: PduRx<'static>,
    chain: Arc<Mutex<Chain>>,
    stop: Arc<AtomicBool>,
) {
    let waker = Waker::from(Arc::new(Unpark(thread::current())));
    let mut buf = [0u8; 1514];
    while !stop.load(Ordering::Relaxed) {
        tx.replace_waker(&waker);
        while let Some(frame) = tx.next_sendable_frame() {
            let mut n = 0;
            let sent = frame.send_blocking(|b| {
                buf[..b.len()].copy_from_slice(b);
                n = b.len();
                Ok(n)
            });
            assert!(sent.is_ok(), "{sent:?}");
            match chain.lock().expect("chain").answer(&mut buf[..n]) {
                Ok(()) => {
                    let received = rx.receive_frame(&buf[..n]);
                    assert!(received.is_ok(), "{received:?}");
                }
                Err(FrameError::Lost) => {}
                Err(e) => panic!("ethercrab's frames are well formed: {e}"),
            }
        }
        thread::park_timeout(Duration::from_millis(1));
    }
}

type Storage = PduStorage<16, { PduStorage::element_size(1100) }>;

/// A chain of `DRIVES` drives on a transport thread, and the MainDevice
/// that talks to it.
struct Wire {
    chain: Arc<Mutex<Chain>>,
    stop: Arc<AtomicBool>,
    thread: thread::JoinHandle<()>,
}

impl Wire {
    fn start(storage: &'static Storage) -> (Self, MainDevice<'static>) {
        let chain = Arc::new(Mutex::new(Chain::new((0..DRIVES).map(|_| SubDevice::servo_drive()).collect())));
        let (tx, rx, pdu_loop) = storage.try_split().expect("split once");
        let stop = Arc::new(AtomicBool::new(false));
        let thread = {
            let (chain, stop) = (chain.clone(), stop.clone());
            thread::spawn(move || transport(tx, rx, chain, stop))
        };
        let md = MainDevice::new(
            pdu_loop,
            Timeouts { pdu: PDU_TIMEOUT, ..Timeouts::default() },
            MainDeviceConfig { dc_static_sync_iterations: 0, ..MainDeviceConfig::default() },
        );
        (Self { chain, stop, thread }, md)
    }

    fn stop(self) {
        self.stop.store(true, Ordering::Relaxed);
        self.thread.join().expect("transport");
    }
}

#[test]
fn ethercrab_brings_the_chain_to_op_and_drives_follow_their_targets() {
    let (wire, md) = Wire::start(&STORAGE);
    let chain = wire.chain.clone();
    futures_lite::future::block_on(async {
        let group = md.init_single_group::<4, 128>(ethercat_now).await.expect("init");
        assert_eq!(group.len(), DRIVES);
        for sd in group.iter(&md) {
            assert_eq!(sd.name(), ethercat_sim::sii::NAME);
            assert_eq!((sd.identity().vendor_id, sd.identity().product_id), (0x0055_504D, 0x402));
            // Cyclic synchronous position, by SDO in PRE-OP.
            sd.sdo_write(0x6060, 0, 8u8).await.expect("0x6060");
            assert_eq!(sd.sdo_read::<u32>(0x1000, 0).await.expect("0x1000"), 0x0002_0192);
            assert!(sd.sdo_read::<u32>(0x2000, 0).await.is_err(), "no such object: aborted");
        }
        let group = group.into_op(&md).await.expect("PRE-OP → OP");
        for sd in group.iter(&md) {
            let io = sd.io_raw();
            assert_eq!((io.inputs().len(), io.outputs().len()), (9, 13));
        }
        // Shutdown → switch on → enable operation, then move.
        let steps: [(u16, i32); 6] = [(0x06, 0), (0x07, 0), (0x0F, 0), (0x0F, 100), (0x0F, 250), (0x0F, -40)];
        for (k, (controlword, target)) in steps.into_iter().enumerate() {
            for (i, sd) in group.iter(&md).enumerate() {
                let mut o = sd.outputs_raw_mut();
                o[..2].copy_from_slice(&controlword.to_le_bytes());
                o[2..6].copy_from_slice(&(target * (i as i32 + 1)).to_le_bytes());
                o[12] = 8;
            }
            let r = group.tx_rx(&md).await.expect("tx_rx");
            assert_eq!(r.working_counter, 3 * DRIVES as u16, "step {k}");
            assert!(r.all_op());
        }
        // Inputs are latched as the frame passes, before the drive acts
        // on the outputs it carries: they show a target one cycle later.
        group.tx_rx(&md).await.expect("tx_rx");
        for (i, sd) in group.iter(&md).enumerate() {
            let inputs = sd.inputs_raw();
            let status = u16::from_le_bytes([inputs[0], inputs[1]]);
            let actual = i32::from_le_bytes([inputs[2], inputs[3], inputs[4], inputs[5]]);
            assert_eq!(status & 0x006F, 0x0027, "drive {i}: operation enabled");
            assert_eq!(actual, -40 * (i as i32 + 1), "drive {i}");
        }
        let group = group.into_safe_op(&md).await.expect("OP → SAFE-OP");
        let _ = group.into_pre_op(&md).await.expect("SAFE-OP → PRE-OP");
    });
    wire.stop();
    let chain = chain.lock().expect("chain");
    for d in &chain.devices {
        assert_eq!(d.al_state(), (al_state::PRE_OP, false));
        assert_eq!(d.drive.mode, 8);
        // Leaving OP stopped the drive.
        assert_ne!(d.drive.state, PowerState::OperationEnabled);
    }
    assert_eq!(chain.refused, 0);
}

#[test]
fn faults_on_the_wire_and_in_a_drive_are_seen_and_recovered() {
    let (wire, md) = Wire::start(&FAULT_STORAGE);
    let chain = wire.chain.clone();
    let full = 3 * DRIVES as u16;
    futures_lite::future::block_on(async {
        let group = md.init_single_group::<4, 128>(ethercat_now).await.expect("init");
        let group = group.into_op(&md).await.expect("op");
        // Outputs for every drive: controlword, target × (i + 1), CSP.
        let set_outputs = |controlword: u16, target: i32| {
            for (i, sd) in group.iter(&md).enumerate() {
                let mut o = sd.outputs_raw_mut();
                o[..2].copy_from_slice(&controlword.to_le_bytes());
                o[2..6].copy_from_slice(&(target * (i as i32 + 1)).to_le_bytes());
                o[12] = 8;
            }
        };
        for cw in [0x06, 0x07, 0x0F] {
            set_outputs(cw, 0);
            group.tx_rx(&md).await.expect("tx_rx");
        }
        // The cable pulled after the first drive: the others stop counting.
        chain.lock().expect("chain").cut_after(1);
        set_outputs(0x0F, 10);
        let r = group.tx_rx(&md).await;
        assert!(r.as_ref().is_ok_and(|r| r.working_counter == 3), "{:?}", r.map(|r| r.working_counter));
        chain.lock().expect("chain").cut_after(DRIVES);
        assert_eq!(group.tx_rx(&md).await.expect("tx_rx").working_counter, full, "plugged back");
        // A lost frame: this exchange times out, the next one works.
        chain.lock().expect("chain").lose_frames(1);
        assert!(group.tx_rx(&md).await.is_err(), "a lost frame is a timeout");
        assert_eq!(group.tx_rx(&md).await.expect("tx_rx").working_counter, full);
        // Drive 1 faults: its statusword says so and it stops following.
        chain.lock().expect("chain").devices[1].drive.fault();
        set_outputs(0x0F, 20);
        group.tx_rx(&md).await.expect("tx_rx");
        group.tx_rx(&md).await.expect("tx_rx");
        let status = |i: usize| {
            let sd = group.iter(&md).nth(i).expect("drive");
            let inputs = sd.inputs_raw();
            (
                u16::from_le_bytes([inputs[0], inputs[1]]),
                i32::from_le_bytes([inputs[2], inputs[3], inputs[4], inputs[5]]),
            )
        };
        assert_ne!(status(1).0 & 0x0008, 0, "fault bit");
        assert_eq!(status(0), (0x0237, 20), "the others go on");
        assert_ne!(status(1).1, 40, "a faulted drive does not follow");
        // Fault reset, then switched on again: it follows.
        for cw in [0x80, 0x06, 0x07, 0x0F, 0x0F, 0x0F] {
            set_outputs(cw, 30);
            group.tx_rx(&md).await.expect("tx_rx");
        }
        assert_eq!(status(1), (0x0237, 60), "recovered");
    });
    wire.stop();
    assert_eq!(chain.lock().expect("chain").devices[1].drive.faults, 1);
}
