//! The Modbus TCP server (tokio-modbus) for PLCs: input registers and the
//! run coil of [`crate::modbus_map`]. Modbus has no users: it binds to
//! localhost unless an address is given. A malformed frame closes its
//! connection (tokio-modbus's codec); other connections go on.

use std::net::SocketAddr;
use std::sync::Arc;
use std::sync::atomic::Ordering::Relaxed;

use ipc_types::{CoreCommand, CoreState};
use tokio_modbus::server::Service;
use tokio_modbus::server::tcp::Server;
use tokio_modbus::{ExceptionCode, Request, Response};

use crate::counters::LineCounters;
use crate::modbus_map::{PICK_ACK_REGISTER, RUN_COIL, input_registers};
use upm_rig_client::rig_view::{PickRefusal, RigView};

/// Connections served at once; more are closed at accept (and counted):
/// a client that never finishes a frame holds its connection.
pub const MAX_CONNECTIONS: usize = 64;

/// One connection's service.
#[derive(Debug)]
struct PlcService {
    view: Arc<RigView>,
    counters: Arc<LineCounters>,
    builtin_robot: bool,
}

impl Drop for PlcService {
    fn drop(&mut self) {
        self.counters.modbus_connections.fetch_sub(1, Relaxed);
    }
}

impl PlcService {
    fn answer(&self, request: Request<'static>) -> Result<Response, ExceptionCode> {
        match request {
            Request::ReadInputRegisters(addr, count) => {
                input_registers(&self.view.snapshot(), addr, count).map(Response::ReadInputRegisters)
            }
            Request::ReadCoils(RUN_COIL, 1) => {
                Ok(Response::ReadCoils(vec![self.view.snapshot().state == CoreState::Running]))
            }
            Request::ReadCoils(_, 0) | Request::ReadCoils(_, 2001..) => Err(ExceptionCode::IllegalDataValue),
            Request::WriteSingleCoil(RUN_COIL, on) => {
                let command = if on { CoreCommand::START } else { CoreCommand::STOP };
                self.view.command(command).map_err(|e| {
                    tracing::warn!("Modbus run coil: {e}");
                    ExceptionCode::ServerDeviceFailure
                })?;
                Ok(Response::WriteSingleCoil(RUN_COIL, on))
            }
            Request::ReadCoils(..) | Request::WriteSingleCoil(..) => Err(ExceptionCode::IllegalDataAddress),
            Request::WriteSingleRegister(PICK_ACK_REGISTER, pose) => {
                match self.view.picked(u32::from(pose), self.builtin_robot) {
                    Ok(()) => Ok(Response::WriteSingleRegister(PICK_ACK_REGISTER, pose)),
                    Err(PickRefusal::OutOfRange) => Err(ExceptionCode::IllegalDataValue),
                    // Modbus has no "invalid state"; a PLC retries on busy.
                    Err(PickRefusal::NotReady | PickRefusal::BuiltinRobot) => {
                        Err(ExceptionCode::ServerDeviceBusy)
                    }
                    Err(PickRefusal::Failed(e)) => {
                        tracing::warn!("Modbus pick acknowledge: {e}");
                        Err(ExceptionCode::ServerDeviceFailure)
                    }
                }
            }
            Request::ReadHoldingRegisters(..)
            | Request::WriteSingleRegister(..)
            | Request::WriteMultipleRegisters(..)
            | Request::WriteMultipleCoils(..)
            | Request::ReadDiscreteInputs(..) => Err(ExceptionCode::IllegalDataAddress),
            _ => Err(ExceptionCode::IllegalFunction),
        }
    }
}

impl Service for PlcService {
    type Request = Request<'static>;
    type Response = Response;
    type Exception = ExceptionCode;
    type Future = std::future::Ready<Result<Response, ExceptionCode>>;

    fn call(&self, request: Self::Request) -> Self::Future {
        let answer = self.answer(request);
        if answer.is_err() {
            LineCounters::count(&self.counters.modbus_exceptions);
        }
        std::future::ready(answer)
    }
}

/// Serve on `addr` until `stop` resolves.
pub async fn serve(
    addr: SocketAddr,
    builtin_robot: bool,
    view: Arc<RigView>,
    counters: Arc<LineCounters>,
    stop: impl std::future::Future<Output = ()> + Send + Sync + 'static,
) -> anyhow::Result<()> {
    let listener = tokio::net::TcpListener::bind(addr)
        .await
        .map_err(|e| anyhow::anyhow!("--modbus {addr}: cannot listen: {e}"))?;
    let server = Server::new(listener);
    let (refused, bad_frames) = (counters.clone(), counters.clone());
    let on_connected = move |stream, peer| {
        let service = if counters.modbus_connections.fetch_add(1, Relaxed) < MAX_CONNECTIONS as u64 {
            Some(PlcService { view: view.clone(), counters: counters.clone(), builtin_robot })
        } else {
            counters.modbus_connections.fetch_sub(1, Relaxed);
            LineCounters::count(&refused.modbus_refused_connections);
            None
        };
        let _ = peer;
        async move { std::io::Result::Ok(service.map(|s| (s, stream))) }
    };
    let on_process_error = move |e: std::io::Error| {
        LineCounters::count(&bad_frames.modbus_bad_frames);
        tracing::debug!("Modbus connection closed: {e}");
    };
    server.serve_until(&on_connected, on_process_error, stop).await?;
    Ok(())
}
