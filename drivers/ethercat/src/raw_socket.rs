//! [`RawSocketWire`]: EtherCAT frames on a NIC (or one end of a veth pair)
//! through an `AF_PACKET` socket ([`RawSocket`]) bound to EtherType 0x88A4.
//!
//! A round trip is a `send` and a bounded wait for the answer: `recv` with
//! the socket's receive timeout as the frame's deadline. Answers that are
//! not the frame just sent (late answers to a frame already given up on,
//! anything else on the wire) are skipped and counted; a frame that does
//! not come back by the deadline is lost. Those two syscalls are the only
//! ones on the motor thread: they are the I/O the motor exists to do. The
//! socket needs CAP_NET_RAW (root, or `setcap cap_net_raw+ep` on upm-core).

use core::fmt;
use std::ffi::CString;
use std::os::fd::{AsRawFd, FromRawFd, OwnedFd};
use std::time::Duration;

use crate::wire::{MAX_FRAME, Wire, WireError};

const ETHERTYPE: u16 = 0x88A4;
/// Where the frame's first datagram keeps its index (Ethernet 14, frame
/// header 2, command 1).
const INDEX_AT: usize = 17;

/// Why the socket could not be opened.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum OpenError {
    /// No interface of that name.
    NoInterface,
    /// `socket`, `bind` or `setsockopt` failed (errno); EPERM without
    /// CAP_NET_RAW.
    Os { call: &'static str, errno: i32 },
}

impl fmt::Display for OpenError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::NoInterface => f.write_str("ethercat: no network interface of that name"),
            Self::Os { call, errno } if *errno == libc::EPERM => write!(
                f,
                "ethercat: {call}: not permitted (a raw socket needs root or `setcap cap_net_raw+ep` on upm-core)"
            ),
            Self::Os { call, errno } => {
                write!(f, "ethercat: {call} failed: {}", std::io::Error::from_raw_os_error(*errno))
            }
        }
    }
}

impl core::error::Error for OpenError {}

/// An `AF_PACKET` socket for EtherCAT frames on one interface, with a
/// receive timeout. Own outgoing frames are not looped back to it.
#[derive(Debug)]
pub struct RawSocket {
    fd: OwnedFd,
}

impl RawSocket {
    /// Open `interface`; a receive waits at most `timeout`.
    pub fn open(interface: &str, timeout: Duration) -> Result<Self, OpenError> {
        let name = CString::new(interface).map_err(|_| OpenError::NoInterface)?;
        // SAFETY: a NUL-terminated name.
        let index = unsafe { libc::if_nametoindex(name.as_ptr()) };
        if index == 0 {
            return Err(OpenError::NoInterface);
        }
        let proto = ETHERTYPE.to_be();
        // SAFETY: plain socket call; the fd is owned right after.
        let raw = unsafe { libc::socket(libc::AF_PACKET, libc::SOCK_RAW, i32::from(proto)) };
        if raw < 0 {
            return Err(OpenError::Os { call: "socket(AF_PACKET)", errno: errno() });
        }
        // SAFETY: `raw` is a fresh descriptor nobody else owns.
        let fd = unsafe { OwnedFd::from_raw_fd(raw) };
        // SAFETY: zeroed sockaddr_ll is valid; fields set below.
        let mut addr: libc::sockaddr_ll = unsafe { core::mem::zeroed() };
        addr.sll_family = libc::AF_PACKET as u16;
        addr.sll_protocol = proto;
        addr.sll_ifindex = index as i32;
        // SAFETY: addr is a sockaddr_ll of the size passed.
        let bound = unsafe {
            libc::bind(
                fd.as_raw_fd(),
                (&raw const addr).cast(),
                core::mem::size_of::<libc::sockaddr_ll>() as libc::socklen_t,
            )
        };
        if bound != 0 {
            return Err(OpenError::Os { call: "bind", errno: errno() });
        }
        let one: libc::c_int = 1;
        set(&fd, libc::SOL_PACKET, libc::PACKET_IGNORE_OUTGOING, &one, "setsockopt(PACKET_IGNORE_OUTGOING)")?;
        let tv = libc::timeval {
            tv_sec: timeout.as_secs() as libc::time_t,
            tv_usec: timeout.subsec_micros().max(1) as libc::suseconds_t,
        };
        set(&fd, libc::SOL_SOCKET, libc::SO_RCVTIMEO, &tv, "setsockopt(SO_RCVTIMEO)")?;
        Ok(Self { fd })
    }

    /// Send one whole frame.
    pub fn send(&self, frame: &[u8]) -> Result<(), WireError> {
        // SAFETY: readable for `frame.len()` bytes.
        let sent = unsafe { libc::send(self.fd.as_raw_fd(), frame.as_ptr().cast(), frame.len(), 0) };
        match sent {
            n if n == frame.len() as isize => Ok(()),
            n if n < 0 => Err(WireError::Io(errno())),
            _ => Err(WireError::Refused),
        }
    }

    /// Receive one frame into `buf` (waiting at most the timeout, or not at
    /// all with `wait` false): its length on the wire, which may exceed
    /// `buf` (the rest is cut).
    pub fn recv(&self, buf: &mut [u8], wait: bool) -> Result<usize, WireError> {
        let flags = libc::MSG_TRUNC | if wait { 0 } else { libc::MSG_DONTWAIT };
        // SAFETY: writable for `buf.len()` bytes.
        let got = unsafe { libc::recv(self.fd.as_raw_fd(), buf.as_mut_ptr().cast(), buf.len(), flags) };
        if got >= 0 {
            return Ok(got as usize);
        }
        let e = errno();
        Err(if e == libc::EAGAIN || e == libc::EWOULDBLOCK { WireError::Lost } else { WireError::Io(e) })
    }
}

fn set<T>(fd: &OwnedFd, level: i32, name: i32, value: &T, call: &'static str) -> Result<(), OpenError> {
    // SAFETY: `value` is a live T of the size passed.
    let r = unsafe {
        libc::setsockopt(
            fd.as_raw_fd(),
            level,
            name,
            (value as *const T).cast(),
            core::mem::size_of::<T>() as libc::socklen_t,
        )
    };
    if r != 0 { Err(OpenError::Os { call, errno: errno() }) } else { Ok(()) }
}

/// An EtherCAT wire on a network interface.
#[derive(Debug)]
pub struct RawSocketWire {
    socket: RawSocket,
    /// Where late answers are drained to.
    scratch: Box<[u8; MAX_FRAME]>,
    /// Answers skipped (not the frame just sent).
    pub stale: u64,
}

/// Foreign or late frames skipped while waiting for one answer, at most
/// (each restarts the receive deadline: a round trip is bounded by
/// `MAX_SKIPPED` deadlines).
const MAX_SKIPPED: u32 = 8;
/// Queued frames drained before a send, at most.
const MAX_DRAINED: u32 = 32;

fn errno() -> i32 {
    std::io::Error::last_os_error().raw_os_error().unwrap_or(0)
}

impl RawSocketWire {
    /// Open `interface`; each frame waits at most `deadline` for its answer.
    pub fn open(interface: &str, deadline: Duration) -> Result<Self, OpenError> {
        Ok(Self {
            socket: RawSocket::open(interface, deadline)?,
            scratch: Box::new([0; MAX_FRAME]),
            stale: 0,
        })
    }
}

impl Wire for RawSocketWire {
    fn round_trip(&mut self, frame: &mut [u8]) -> Result<(), WireError> {
        let len = frame.len();
        let Some(&index) = frame.get(INDEX_AT) else { return Err(WireError::Refused) };
        // Answers that came after their frame was given up on (bounded:
        // a wire flooded with EtherCAT frames cannot hold the caller).
        for _ in 0..MAX_DRAINED {
            if self.socket.recv(&mut self.scratch[..], false).is_err() {
                break;
            }
            self.stale += 1;
        }
        self.socket.send(frame)?;
        for _ in 0..MAX_SKIPPED {
            let got = self.socket.recv(frame, true)?;
            // An answer is the frame sent, as long or padded longer.
            if got >= len && frame[INDEX_AT] == index {
                return Ok(());
            }
            self.stale += 1;
        }
        Err(WireError::Lost)
    }
}
