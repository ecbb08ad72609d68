//! The cross-process contract: type names carry the protocol version and
//! service names are valid iceoryx2 names.

use iceoryx2::prelude::{ServiceName, ZeroCopySend};
use ipc_types::{
    CoreCommand, ExplicitSchedule, ForceRequest, PROTOCOL_VERSION, PartStates, Schedule, Telemetry,
    service_names,
};

fn type_name<T: ZeroCopySend>() -> &'static str {
    // SAFETY: only reads the name the derive generated.
    unsafe { <T as ZeroCopySend>::type_name() }
}

#[test]
fn payload_type_names_carry_the_protocol_version() {
    let suffix = format!(".v{PROTOCOL_VERSION}");
    let names = [
        type_name::<PartStates>(),
        type_name::<ForceRequest>(),
        type_name::<ExplicitSchedule>(),
        type_name::<Schedule>(),
        type_name::<Telemetry>(),
        type_name::<CoreCommand>(),
    ];
    for name in names {
        assert!(name.starts_with("upm::") && name.ends_with(&suffix), "{name} lacks upm::…{suffix}");
    }
    let mut unique = names.to_vec();
    unique.sort_unstable();
    unique.dedup();
    assert_eq!(unique.len(), names.len(), "type names must differ: {names:?}");
}

#[test]
fn service_names_are_valid_and_distinct() {
    for name in service_names::ALL {
        assert!(ServiceName::new(name).is_ok(), "{name} is not a valid iceoryx2 service name");
        assert!(name.starts_with("upm/"), "{name}");
    }
    let mut unique = service_names::ALL.to_vec();
    unique.sort_unstable();
    unique.dedup();
    assert_eq!(unique.len(), service_names::ALL.len());
}

#[test]
fn monotonic_clock_moves_forward() {
    let a = ipc_types::monotonic_now_ns();
    std::thread::sleep(std::time::Duration::from_millis(2));
    let b = ipc_types::monotonic_now_ns();
    assert!(a > 0 && b >= a + 1_000_000, "a={a} b={b}");
}
