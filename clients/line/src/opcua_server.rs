//! The OPC UA server (async-opcua): the `Rig` object in namespace
//! `urn:upm:rig` with string node ids, its variables updated at the
//! camera's rate from the [`RigView`], and its methods. Anonymous sessions
//! read; method calls need a user of the users file (docs/line.md lists
//! every node).

use std::net::SocketAddr;
use std::path::PathBuf;
use std::sync::Arc;
use std::time::Duration;

use async_trait::async_trait;
use ipc_types::CoreCommand;
use opcua::crypto::SecurityPolicy;
use opcua::server::address_space::{AccessLevel, MethodBuilder, ObjectBuilder, VariableBuilder};
use opcua::server::authenticator::{AuthManager, Password, UserToken, user_pass_security_policy_id};
use opcua::server::diagnostics::NamespaceMetadata;
use opcua::server::node_manager::memory::{SimpleNodeManager, simple_node_manager};
use opcua::server::{ANONYMOUS_USER_TOKEN_ID, ServerBuilder, ServerEndpoint, ServerHandle};
use opcua::types::{
    DataTypeId, DataValue, DateTime, Error, MessageSecurityMode, NodeId, ObjectId, ObjectTypeId,
    QualifiedName, StatusCode, UAString, UserTokenPolicy, UserTokenType, VariableId, VariableTypeId, Variant,
};
use upm_users::Users;

use crate::counters::LineCounters;
use upm_rig_client::rig_view::{PickRefusal, PoseView, RigSnapshot, RigView};

pub const NAMESPACE_URI: &str = "urn:upm:rig";
/// The `Picked(UInt32 pose)` method's node id (its browse name is
/// `Picked`; the count `Rig.Picked` is browsed as `PickedCount`).
pub const PICKED_METHOD: &str = "Rig.PickedMethod";
/// How often the variables are refreshed (the cell's status comes at the
/// camera's rate; this keeps the line's share of the delay small).
const UPDATE_PERIOD: Duration = Duration::from_millis(10);
/// The shortest publishing and sampling intervals a client may ask.
const MIN_INTERVAL_MS: f64 = 10.0;
/// A failed login waits this long before its answer: guessing is slow.
const LOGIN_FAILURE_DELAY: Duration = Duration::from_secs(1);

/// Where and how to serve.
#[derive(Debug, Clone)]
pub struct OpcUaOptions {
    pub addr: SocketAddr,
    /// The server's certificate and key (made on first start), and the
    /// client certificates it trusts (`trusted/`) or refused (`rejected/`).
    pub pki_dir: PathBuf,
    pub users: Users,
    /// The simulator's own robot picks: `Rig.Picked` is refused.
    pub builtin_robot: bool,
    /// Where `LoadRecipe(NAME)` finds `NAME.toml`.
    pub recipes_dir: PathBuf,
}

/// Anonymous sessions read; users of the file may call methods and write.
#[derive(Debug)]
struct RigAuth {
    users: Arc<Users>,
    counters: Arc<LineCounters>,
}

#[async_trait]
impl AuthManager for RigAuth {
    async fn authenticate_anonymous_token(&self, _endpoint: &ServerEndpoint) -> Result<(), Error> {
        Ok(())
    }

    async fn authenticate_username_identity_token(
        &self,
        _endpoint: &ServerEndpoint,
        username: &str,
        password: &Password,
    ) -> Result<UserToken, Error> {
        let (users, name, pw) = (self.users.clone(), username.to_owned(), password.get().to_owned());
        // argon2 costs tens of ms: off the server's async workers.
        let ok = tokio::task::spawn_blocking(move || users.verify(&name, &pw)).await.unwrap_or(false);
        if ok {
            return Ok(UserToken(username.to_owned()));
        }
        LineCounters::count(&self.counters.login_failures);
        tokio::time::sleep(LOGIN_FAILURE_DELAY).await;
        Err(Error::new(StatusCode::BadUserAccessDenied, "unknown user or wrong password"))
    }

    fn user_token_policies(&self, endpoint: &ServerEndpoint) -> Vec<UserTokenPolicy> {
        let policy = |policy_id: UAString, token_type| UserTokenPolicy {
            policy_id,
            token_type,
            issued_token_type: UAString::null(),
            issuer_endpoint_url: UAString::null(),
            security_policy_uri: UAString::null(),
        };
        vec![
            policy("anonymous".into(), UserTokenType::Anonymous),
            policy(user_pass_security_policy_id(endpoint), UserTokenType::UserName),
        ]
    }

    fn is_user_executable(&self, token: &UserToken, _method: &NodeId) -> bool {
        let allowed = !token.is_anonymous();
        if !allowed {
            LineCounters::count(&self.counters.access_denied);
        }
        allowed
    }

    fn effective_user_access_level(
        &self,
        token: &UserToken,
        level: AccessLevel,
        _node: &NodeId,
    ) -> AccessLevel {
        if token.is_anonymous() { level - AccessLevel::CURRENT_WRITE } else { level }
    }
}

/// The nodes, by their string ids.
struct Nodes {
    ns: u16,
}

impl Nodes {
    fn id(&self, s: &str) -> NodeId {
        NodeId::new(self.ns, s)
    }
    fn name(&self, s: &str) -> QualifiedName {
        QualifiedName::new(self.ns, s)
    }
}

/// The rig's scalar variables: (id under `Rig.`, type, value).
fn rig_values(s: &RigSnapshot, counters: &LineCounters) -> Vec<(String, DataTypeId, Variant)> {
    let mut v = vec![
        ("State".to_owned(), DataTypeId::String, Variant::from(s.state.as_str())),
        ("Health".to_owned(), DataTypeId::String, Variant::from(s.health.as_str())),
        ("Recipe".to_owned(), DataTypeId::String, Variant::from(s.recipe.as_str())),
        ("RecipeError".to_owned(), DataTypeId::String, Variant::from(s.recipe_error.as_str())),
        ("Picked".to_owned(), DataTypeId::UInt64, Variant::from(s.picked)),
        ("Lost".to_owned(), DataTypeId::UInt64, Variant::from(s.lost)),
        ("PartsPerMinute".to_owned(), DataTypeId::Double, Variant::from(s.parts_per_minute)),
        ("PoseCount".to_owned(), DataTypeId::UInt32, Variant::from(s.poses.len() as u32)),
    ];
    for (name, value) in counters.all() {
        v.push((format!("Line.{name}"), DataTypeId::UInt64, Variant::from(value)));
    }
    v
}

/// Pose `n`'s variables: (id under `Rig.Pick.n.`, type, value). A pose
/// the running recipe no longer has reads empty and never ready.
fn pose_values(s: &RigSnapshot, n: usize) -> Vec<(&'static str, DataTypeId, Variant)> {
    const GONE: PoseView = PoseView { ready: false, class: -1, part_id: 0, x: 0.0, y: 0.0, theta: 0.0 };
    let p = s.poses.get(n).unwrap_or(&GONE);
    vec![
        ("Ready", DataTypeId::Boolean, Variant::from(p.ready)),
        ("Class", DataTypeId::Int32, Variant::from(p.class)),
        ("PartId", DataTypeId::UInt32, Variant::from(p.part_id)),
        ("X", DataTypeId::Double, Variant::from(p.x)),
        ("Y", DataTypeId::Double, Variant::from(p.y)),
        ("Theta", DataTypeId::Double, Variant::from(p.theta)),
    ]
}

/// A method's one argument, as `of` takes it; a missing, extra or
/// mistyped argument is refused with its status code and counted.
fn one_argument<T>(
    args: &[Variant],
    counters: &LineCounters,
    of: impl Fn(&Variant) -> Option<T>,
) -> Result<T, StatusCode> {
    let refused = match args {
        [v] => match of(v) {
            Some(t) => return Ok(t),
            None => StatusCode::BadTypeMismatch,
        },
        [] => StatusCode::BadArgumentsMissing,
        _ => StatusCode::BadTooManyArguments,
    };
    LineCounters::count(&counters.bad_arguments);
    Err(refused)
}

/// Serve until `handle` is cancelled. Returns the handle at once (the
/// server runs on the current tokio runtime).
pub async fn serve(
    opts: OpcUaOptions,
    view: Arc<RigView>,
    counters: Arc<LineCounters>,
) -> anyhow::Result<(ServerHandle, tokio::task::JoinHandle<()>)> {
    let host = opts.addr.ip().to_string();
    let url = format!("opc.tcp://{}/", opts.addr);
    let ids: &[&str] = &[ANONYMOUS_USER_TOKEN_ID];
    let auth = Arc::new(RigAuth { users: Arc::new(opts.users), counters: counters.clone() });
    let mut builder = ServerBuilder::new();
    // A robot waits on `Ready`: let it subscribe faster than the crate's
    // 100 ms floor.
    let limits = &mut builder.limits_mut().subscriptions;
    (limits.min_publishing_interval_ms, limits.min_sampling_interval_ms) = (MIN_INTERVAL_MS, MIN_INTERVAL_MS);
    let (server, handle) = builder
        .application_name("UPM rig")
        .application_uri("urn:upm:rig:line")
        .product_uri("urn:upm:rig")
        .host(host)
        .port(opts.addr.port())
        .pki_dir(&opts.pki_dir)
        .create_sample_keypair(true)
        .trust_client_certs(false)
        .with_authenticator(auth)
        .add_endpoint("none", ("/", SecurityPolicy::None, MessageSecurityMode::None, ids))
        .add_endpoint(
            "basic256sha256",
            ("/", SecurityPolicy::Basic256Sha256, MessageSecurityMode::SignAndEncrypt, ids),
        )
        .discovery_urls(vec![url])
        // The server looks at its subscriptions on one timer (100 ms
        // unless set): at the interval it grants, or `Ready` waits for it.
        .subscription_poll_interval_ms(MIN_INTERVAL_MS as u64)
        // For the open-session count `upm status` shows.
        .diagnostics_enabled(true)
        .with_node_manager(simple_node_manager(
            NamespaceMetadata { namespace_uri: NAMESPACE_URI.to_owned(), ..Default::default() },
            "rig",
        ))
        .build()
        .map_err(|e| anyhow::anyhow!("the OPC UA server's configuration: {e}"))?;
    let nm = handle
        .node_managers()
        .get_of_type::<SimpleNodeManager>()
        .ok_or_else(|| anyhow::anyhow!("the OPC UA server has no node manager"))?;
    let ns = handle
        .get_namespace_index(NAMESPACE_URI)
        .ok_or_else(|| anyhow::anyhow!("the OPC UA server has no namespace {NAMESPACE_URI}"))?;
    let nodes = Nodes { ns };
    let rig = nodes.id("Rig");
    let first = view.snapshot();
    {
        let mut space = nm.address_space().write();
        ObjectBuilder::new(&rig, nodes.name("Rig"), "Rig")
            .organized_by(ObjectId::ObjectsFolder)
            .has_type_definition(ObjectTypeId::BaseObjectType)
            .insert(&mut *space);
        for (name, ty, value) in rig_values(&first, &counters) {
            // The method `Picked` has the browse name; the count is `PickedCount`.
            let browse = if name == "Picked" { "PickedCount".to_owned() } else { name.clone() };
            VariableBuilder::new(&nodes.id(&format!("Rig.{name}")), nodes.name(&browse), name.as_str())
                .data_type(ty)
                .value(value)
                .component_of(rig.clone())
                .has_type_definition(VariableTypeId::BaseDataVariableType)
                .insert(&mut *space);
        }
        for method in ["Start", "Stop", "Resume"] {
            MethodBuilder::new(&nodes.id(&format!("Rig.{method}")), nodes.name(method), method)
                .component_of(rig.clone())
                .executable(true)
                .user_executable(true)
                .insert(&mut *space);
        }
        MethodBuilder::new(&nodes.id(PICKED_METHOD), nodes.name("Picked"), "Picked")
            .component_of(rig.clone())
            .executable(true)
            .user_executable(true)
            .input_args(
                &mut *space,
                &nodes.id(&format!("{PICKED_METHOD}.InputArguments")),
                &[("pose", DataTypeId::UInt32).into()],
            )
            .insert(&mut *space);
        MethodBuilder::new(&nodes.id("Rig.LoadRecipe"), nodes.name("LoadRecipe"), "LoadRecipe")
            .component_of(rig.clone())
            .executable(true)
            .user_executable(true)
            .input_args(
                &mut *space,
                &nodes.id("Rig.LoadRecipe.InputArguments"),
                &[("recipe", DataTypeId::String).into()],
            )
            .insert(&mut *space);
    }
    {
        let (view, counters, dir) = (view.clone(), counters.clone(), opts.recipes_dir.clone());
        let (space, subscriptions) = (nm.clone(), handle.subscriptions().clone());
        let ids = [nodes.id("Rig.Recipe"), nodes.id("Rig.RecipeError")];
        // A client reading right after the call sees its outcome.
        let show_recipe = move |s: &RigSnapshot| {
            let now = DateTime::now();
            let values = [
                DataValue::new_at(Variant::from(s.recipe.as_str()), now),
                DataValue::new_at(Variant::from(s.recipe_error.as_str()), now),
            ];
            let _ = space.set_values(
                &subscriptions,
                ids.iter().zip(values.iter()).map(|(id, v)| (id, None, v.clone())),
            );
        };
        nm.inner().add_method_callback(nodes.id("Rig.LoadRecipe"), move |args: &[Variant]| {
            let name = one_argument(args, &counters, |v| match v {
                Variant::String(name) => Some(name.as_ref().to_owned()),
                _ => None,
            })?;
            // Loading and the core's answer take milliseconds: off the async workers' queue.
            let outcome = tokio::task::block_in_place(|| view.load_recipe(&name, &dir));
            show_recipe(&view.snapshot());
            match outcome {
                Ok(path) => {
                    tracing::info!("Rig.LoadRecipe: the cell runs {path}");
                    Ok(Vec::new())
                }
                Err(why) => {
                    tracing::warn!("Rig.LoadRecipe({name:?}): {why}");
                    Err(StatusCode::BadInvalidArgument)
                }
            }
        });
    }
    {
        let (view, counters, builtin) = (view.clone(), counters.clone(), opts.builtin_robot);
        nm.inner().add_method_callback(nodes.id(PICKED_METHOD), move |args: &[Variant]| {
            let pose = one_argument(args, &counters, |v| match v {
                Variant::UInt32(pose) => Some(*pose),
                _ => None,
            })?;
            view.picked(pose, builtin).map(|()| Vec::new()).map_err(|refusal| {
                let (counter, code) = match refusal {
                    PickRefusal::OutOfRange => (&counters.bad_arguments, StatusCode::BadOutOfRange),
                    PickRefusal::NotReady | PickRefusal::BuiltinRobot => {
                        (&counters.invalid_state, StatusCode::BadInvalidState)
                    }
                    PickRefusal::Failed(e) => {
                        tracing::warn!("Rig.Picked: {e}");
                        (&counters.failed_calls, StatusCode::BadInternalError)
                    }
                };
                LineCounters::count(counter);
                code
            })
        });
    }
    for (method, command) in
        [("Start", CoreCommand::START), ("Stop", CoreCommand::STOP), ("Resume", CoreCommand::RESUME)]
    {
        let (view, counters) = (view.clone(), counters.clone());
        nm.inner().add_method_callback(nodes.id(&format!("Rig.{method}")), move |args: &[Variant]| {
            if !args.is_empty() {
                LineCounters::count(&counters.bad_arguments);
                return Err(StatusCode::BadTooManyArguments);
            }
            view.command(command).map(|()| Vec::new()).map_err(|e| {
                tracing::warn!("Rig.{method}: {e}");
                LineCounters::count(&counters.failed_calls);
                StatusCode::BadInternalError
            })
        });
    }
    let subscriptions = handle.subscriptions().clone();
    let token = handle.token().clone();
    let info = handle.info().clone();
    let updater = tokio::spawn(async move {
        let mut tick = tokio::time::interval(UPDATE_PERIOD);
        tick.set_missed_tick_behavior(tokio::time::MissedTickBehavior::Skip);
        let mut poses_made = 0;
        loop {
            tokio::select! {
                _ = tick.tick() => {}
                () = token.cancelled() => break,
            }
            let s = view.snapshot();
            let sessions = info
                .diagnostics
                .get(VariableId::Server_ServerDiagnostics_ServerDiagnosticsSummary_CurrentSessionCount)
                .and_then(|v| match v.value {
                    Some(Variant::UInt32(n)) => Some(u64::from(n)),
                    _ => None,
                });
            counters.opcua_sessions.store(sessions.unwrap_or(0), std::sync::atomic::Ordering::Relaxed);
            // Pick poses appear with the cell's first status.
            if s.poses.len() > poses_made {
                let mut space = nm.address_space().write();
                for n in poses_made..s.poses.len() {
                    for (name, ty, value) in pose_values(&s, n) {
                        let id = format!("Rig.Pick.{n}.{name}");
                        VariableBuilder::new(
                            &nodes.id(&id),
                            nodes.name(&format!("Pick.{n}.{name}")),
                            id.as_str(),
                        )
                        .data_type(ty)
                        .value(value)
                        .component_of(rig.clone())
                        .has_type_definition(VariableTypeId::BaseDataVariableType)
                        .insert(&mut *space);
                    }
                }
                poses_made = s.poses.len();
            }
            let now = DateTime::now();
            let mut values: Vec<(NodeId, DataValue)> = rig_values(&s, &counters)
                .into_iter()
                .map(|(name, _, v)| (nodes.id(&format!("Rig.{name}")), DataValue::new_at(v, now)))
                .collect();
            for n in 0..poses_made {
                for (name, _, v) in pose_values(&s, n) {
                    values.push((nodes.id(&format!("Rig.Pick.{n}.{name}")), DataValue::new_at(v, now)));
                }
            }
            if let Err(e) = nm.set_values(&subscriptions, values.iter().map(|(id, v)| (id, None, v.clone())))
            {
                tracing::warn!("updating the OPC UA variables: {e}");
            }
        }
    });
    let server_task = tokio::spawn(async move {
        if let Err(e) = server.run().await {
            tracing::error!("the OPC UA server stopped: {e}");
        }
    });
    // The updater ends with the server's token; it needs no handle.
    drop(updater);
    Ok((handle, server_task))
}
