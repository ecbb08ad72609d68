//! The page's HTTP routes (docs/hmi.md lists them): the page and its
//! assets, the live WebSocket and a status endpoint for anyone; login,
//! logout and the controls, which need a session cookie (HttpOnly,
//! SameSite=Strict) from a login against the users file.

use std::net::SocketAddr;
use std::path::PathBuf;
use std::sync::Arc;
use std::sync::atomic::Ordering::Relaxed;

use axum::extract::rejection::JsonRejection;
use axum::extract::ws::{Message, Utf8Bytes, WebSocket, WebSocketUpgrade};
use axum::extract::{ConnectInfo, Path, State};
use axum::http::{StatusCode, header};
use axum::response::{Html, IntoResponse, Response};
use axum::routing::{get, post};
use axum::{Json, Router};
use axum_extra::extract::cookie::{Cookie, CookieJar, SameSite};
use ipc_types::CoreCommand;
use serde::Deserialize;
use serde_json::json;
use tokio::sync::watch;
use upm_rig_client::rig_view::RigView;
use upm_users::Users;

use crate::assets;
use crate::counters::HmiCounters;
use crate::live_message::live_json;
use crate::login_throttle::LoginThrottle;
use crate::sessions::{COOKIE, Sessions};
use crate::trails::Trails;

/// Live connections served at once; more are refused (and counted).
pub const MAX_LIVE: u64 = 256;

/// What every handler shares.
#[derive(Debug)]
pub struct AppState {
    pub prefix: String,
    pub view: Arc<RigView>,
    pub users: Arc<Users>,
    pub sessions: Sessions,
    pub throttle: LoginThrottle,
    pub counters: Arc<HmiCounters>,
    /// The newest page state (`live_message::publish` writes it).
    pub live: Arc<watch::Sender<Utf8Bytes>>,
    /// Where "load recipe" NAME finds NAME.toml.
    pub recipes_dir: PathBuf,
    /// Turns true when the server stops: open pages are closed.
    pub stop: watch::Receiver<bool>,
}

pub fn router(state: Arc<AppState>) -> Router {
    Router::new()
        .route("/", get(page))
        .route("/app.js", get(script))
        .route("/style.css", get(style))
        .route("/ws", get(live_socket))
        .route("/api/live", get(live_now))
        .route("/api/status", get(status))
        .route("/api/login", post(login))
        .route("/api/logout", post(logout))
        .route("/api/command/{name}", post(command))
        .route("/api/recipe", post(load_recipe))
        .with_state(state)
}

async fn page() -> Html<&'static str> {
    Html(assets::INDEX_HTML)
}

async fn script() -> impl IntoResponse {
    ([(header::CONTENT_TYPE, "text/javascript; charset=utf-8")], assets::APP_JS)
}

async fn style() -> impl IntoResponse {
    ([(header::CONTENT_TYPE, "text/css; charset=utf-8")], assets::STYLE_CSS)
}

/// An error answer: one line, as JSON.
fn refusal(code: StatusCode, why: impl Into<String>) -> Response {
    (code, Json(json!({ "error": why.into() }))).into_response()
}

/// A body that is not the JSON asked for: counted, one line.
fn bad_body(s: &AppState, e: &JsonRejection) -> Response {
    HmiCounters::count(&s.counters.bad_requests);
    refusal(e.status(), e.body_text().replace('\n', " "))
}

/// The logged-in user; None (counted) without a live session.
fn operator(s: &AppState, jar: &CookieJar) -> Option<String> {
    let user = jar.get(COOKIE).and_then(|c| s.sessions.user(c.value()));
    if user.is_none() {
        HmiCounters::count(&s.counters.unauthorized);
    }
    user
}

fn login_first() -> Response {
    refusal(StatusCode::UNAUTHORIZED, "log in first: the controls need an operator")
}

async fn status(State(s): State<Arc<AppState>>, jar: CookieJar) -> Json<serde_json::Value> {
    let user = jar.get(COOKIE).and_then(|c| s.sessions.user(c.value()));
    let counters: serde_json::Map<String, serde_json::Value> =
        s.counters.all().iter().map(|&(k, v)| (k.to_owned(), json!(v))).collect();
    Json(json!({ "prefix": s.prefix, "user": user, "counters": counters }))
}

/// The page's state now (without trails), for a client without WebSocket.
async fn live_now(State(s): State<Arc<AppState>>) -> Json<serde_json::Value> {
    Json(live_json(&s.view.snapshot(), &Trails::default()))
}

#[derive(Debug, Deserialize)]
struct Login {
    user: String,
    password: String,
}

async fn login(
    State(s): State<Arc<AppState>>,
    ConnectInfo(peer): ConnectInfo<SocketAddr>,
    jar: CookieJar,
    body: Result<Json<Login>, JsonRejection>,
) -> Response {
    let Login { user, password } = match body {
        Ok(Json(l)) => l,
        Err(e) => return bad_body(&s, &e),
    };
    let client = peer.ip();
    // Slowed before the check, so a guesser waits whatever it sends.
    tokio::time::sleep(s.throttle.delay(client)).await;
    let (users, name) = (s.users.clone(), user.clone());
    // argon2 costs tens of ms: off the async workers.
    let ok = tokio::task::spawn_blocking(move || users.verify(&name, &password)).await.unwrap_or(false);
    if !ok {
        HmiCounters::count(&s.counters.login_failures);
        let n = s.throttle.failed(client);
        eprintln!(
            "upm-hmi: login refused for {user:?} from {client} ({n} in a row; its next login waits {:.1} s)",
            s.throttle.delay(client).as_secs_f64()
        );
        return refusal(StatusCode::UNAUTHORIZED, "unknown user or wrong password");
    }
    s.throttle.succeeded(client);
    let token = match s.sessions.open(&user) {
        Ok(t) => t,
        Err(e) => return refusal(StatusCode::INTERNAL_SERVER_ERROR, e.to_string()),
    };
    HmiCounters::count(&s.counters.logins);
    eprintln!("upm-hmi: {user:?} logged in from {client}");
    let cookie = Cookie::build((COOKIE, token)).http_only(true).same_site(SameSite::Strict).path("/").build();
    (jar.add(cookie), Json(json!({ "user": user }))).into_response()
}

async fn logout(State(s): State<Arc<AppState>>, jar: CookieJar) -> Response {
    if let Some(c) = jar.get(COOKIE) {
        s.sessions.close(c.value());
    }
    (jar.remove(Cookie::build(COOKIE).path("/")), Json(json!({ "user": null }))).into_response()
}

async fn command(State(s): State<Arc<AppState>>, jar: CookieJar, Path(name): Path<String>) -> Response {
    let Some(user) = operator(&s, &jar) else { return login_first() };
    let code = match name.as_str() {
        "start" => CoreCommand::START,
        "stop" => CoreCommand::STOP,
        "resume" => CoreCommand::RESUME,
        _ => {
            HmiCounters::count(&s.counters.bad_requests);
            return refusal(StatusCode::NOT_FOUND, format!("no command {name:?}: start, stop or resume"));
        }
    };
    let view = s.view.clone();
    // The view answers within a second: off the async workers.
    let sent = tokio::task::spawn_blocking(move || view.command(code))
        .await
        .unwrap_or_else(|e| Err(format!("the command's task failed: {e}")));
    match sent {
        Ok(()) => {
            HmiCounters::count(&s.counters.commands_sent);
            eprintln!("upm-hmi: {user:?} sent {name}");
            Json(json!({ "sent": name })).into_response()
        }
        Err(why) => {
            HmiCounters::count(&s.counters.commands_failed);
            eprintln!("upm-hmi: {user:?}'s {name} was not sent: {why}");
            refusal(StatusCode::BAD_GATEWAY, why)
        }
    }
}

#[derive(Debug, Deserialize)]
struct RecipeName {
    name: String,
}

async fn load_recipe(
    State(s): State<Arc<AppState>>,
    jar: CookieJar,
    body: Result<Json<RecipeName>, JsonRejection>,
) -> Response {
    let Some(user) = operator(&s, &jar) else { return login_first() };
    let name = match body {
        Ok(Json(r)) => r.name,
        Err(e) => return bad_body(&s, &e),
    };
    let (view, dir, asked) = (s.view.clone(), s.recipes_dir.clone(), name.clone());
    // Loading and the core's answer take up to two seconds: off the async workers.
    let outcome = tokio::task::spawn_blocking(move || view.load_recipe(&asked, &dir))
        .await
        .unwrap_or_else(|e| Err(format!("the changeover's task failed: {e}")));
    match outcome {
        Ok(path) => {
            eprintln!("upm-hmi: {user:?} loaded recipe {path}");
            Json(json!({ "recipe": path })).into_response()
        }
        Err(why) => {
            eprintln!("upm-hmi: {user:?}'s recipe {name:?} refused: {why}");
            refusal(StatusCode::UNPROCESSABLE_ENTITY, why)
        }
    }
}

async fn live_socket(State(s): State<Arc<AppState>>, ws: WebSocketUpgrade) -> Response {
    if s.counters.live_open.load(Relaxed) >= MAX_LIVE {
        HmiCounters::count(&s.counters.bad_requests);
        return refusal(StatusCode::SERVICE_UNAVAILABLE, format!("{MAX_LIVE} pages are open already"));
    }
    ws.on_upgrade(move |socket| serve_live(socket, s))
}

/// Open-connection gauge that cannot miss its decrement.
struct Open(Arc<HmiCounters>);

impl Drop for Open {
    fn drop(&mut self) {
        self.0.live_open.fetch_sub(1, Relaxed);
    }
}

/// Push each new page state until the browser goes or the server stops.
async fn serve_live(mut socket: WebSocket, s: Arc<AppState>) {
    HmiCounters::count(&s.counters.live_connections);
    s.counters.live_open.fetch_add(1, Relaxed);
    let _open = Open(s.counters.clone());
    let mut newest = s.live.subscribe();
    let mut stop = s.stop.clone();
    loop {
        tokio::select! {
            _ = stop.changed() => {
                let _ = socket.send(Message::Close(None)).await;
                break;
            }
            changed = newest.changed() => {
                if changed.is_err() {
                    break;
                }
                let text = newest.borrow_and_update().clone();
                if socket.send(Message::Text(text)).await.is_err() {
                    break;
                }
            }
            incoming = socket.recv() => match incoming {
                Some(Ok(Message::Close(_)) | Err(_)) | None => break,
                Some(Ok(_)) => {}
            },
        }
    }
}
