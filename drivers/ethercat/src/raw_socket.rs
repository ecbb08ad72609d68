//! [`RawSocketWire`]: EtherCAT frames on a NIC (or one end of a veth pair)
//! through an `AF_PACKET` socket bound to EtherType 0x88A4.
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

/// An EtherCAT wire on a network interface.
#[derive(Debug)]
pub struct RawSocketWire {
    fd: OwnedFd,
    /// Where late answers are drained to.
    scratch: Box<[u8; MAX_FRAME]>,
    /// Answers skipped (not the frame just sent).
    pub stale: u64,
}

/// Foreign or late frames skipped while waiting for one answer, at most.
const MAX_SKIPPED: u32 = 8;

fn errno() -> i32 {
    std::io::Error::last_os_error().raw_os_error().unwrap_or(0)
}

impl RawSocketWire {
    /// Open `interface`; each frame waits at most `deadline` for its answer.
    pub fn open(interface: &str, deadline: Duration) -> Result<Self, OpenError> {
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
            tv_sec: deadline.as_secs() as libc::time_t,
            tv_usec: deadline.subsec_micros().max(1) as libc::suseconds_t,
        };
        set(&fd, libc::SOL_SOCKET, libc::SO_RCVTIMEO, &tv, "setsockopt(SO_RCVTIMEO)")?;
        Ok(Self { fd, scratch: Box::new([0; MAX_FRAME]), stale: 0 })
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

impl Wire for RawSocketWire {
    fn round_trip(&mut self, frame: &mut [u8]) -> Result<(), WireError> {
        let len = frame.len();
        let Some(&index) = frame.get(INDEX_AT) else { return Err(WireError::Refused) };
        let fd = self.fd.as_raw_fd();
        // Answers that came after their frame was given up on.
        let scratch = self.scratch.as_mut_ptr().cast();
        // SAFETY: `scratch` is writable for MAX_FRAME bytes.
        while unsafe { libc::recv(fd, scratch, MAX_FRAME, libc::MSG_DONTWAIT) } >= 0 {
            self.stale += 1;
        }
        // SAFETY: readable for `len` bytes; a short send is an error below.
        let sent = unsafe { libc::send(fd, frame.as_ptr().cast(), len, 0) };
        if sent != len as isize {
            return Err(if sent < 0 { WireError::Io(errno()) } else { WireError::Refused });
        }
        for _ in 0..MAX_SKIPPED {
            // SAFETY: writable for `len` bytes; MSG_TRUNC gives the real length.
            let got = unsafe { libc::recv(fd, frame.as_mut_ptr().cast(), len, libc::MSG_TRUNC) };
            if got < 0 {
                let e = errno();
                return Err(if e == libc::EAGAIN || e == libc::EWOULDBLOCK {
                    WireError::Lost
                } else {
                    WireError::Io(e)
                });
            }
            // An answer is the frame sent, as long or padded longer.
            if got as usize >= len && frame[INDEX_AT] == index {
                return Ok(());
            }
            self.stale += 1;
        }
        Err(WireError::Lost)
    }
}
