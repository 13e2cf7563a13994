//! `yokai serve`: play Yōkai with agents in a browser, watch agents, replay games, and
//! collect human–agent games.
//!
//! A small HTTP server (axum) with the page's assets built into the binary (no Node, no
//! build step). The server owns every game: the page sends an action's index, the server
//! checks it against the rules (anything else is a JSON error naming what was wrong, and
//! the game is unchanged), plays the bots, writes the game's record and answers with the
//! seat's view. A game is recorded after every action under `--records`/SESSION/GAME.jsonl
//! (replay JSONL with the seats' names), so a reloaded page, or a restarted server,
//! continues it.
//!
//! The server is safe to open to a network (docs/play.md, "What a study server exposes"):
//! a client names games and seats only from what the operator offered ([`catalog`]), no
//! answer carries a file's text ([`error`]), sessions are ids the server issued
//! ([`sessions`]), and bodies, games and sessions are bounded ([`limits`]).
//!
//! API (JSON; `session` is an id from `POST /api/sessions`, under which its games are
//! filed):
//! - `GET  /api/config`: the default game and seats, and every game and seat on offer;
//! - `POST /api/sessions`: a new session `{session}`;
//! - `POST /api/games` `{session, config?, seats?, seed?}`: a new game;
//! - `GET  /api/games/{id}?session=S&since=K`: the game, with the boards after each step
//!   since step K (to show the bots' moves one at a time);
//! - `POST /api/games/{id}/actions` `{session, seat, action}`: play an action index;
//! - `POST /api/games/{id}/reveal` `{session}`: lift the hot-seat curtain;
//! - `GET  /api/games/{id}/replay?session=S`: the record as replay JSONL;
//! - `POST /api/replay` (replay JSONL): every board of a replay, all colours shown;
//! - `GET  /api/summary?session=S`: R, SEE, EE, WEE, LEN over the session's finished games.

mod catalog;
mod error;
mod limits;
mod records;
mod sessions;
mod tables;
mod view;

use anyhow::Context;
use axum::extract::rejection::{PathRejection, QueryRejection, StringRejection};
use axum::extract::{DefaultBodyLimit, Path as UrlPath, Query, State};
use axum::http::{header, StatusCode};
use axum::response::{IntoResponse, Response};
use axum::routing::{get, post};
use axum::{Json, Router};
pub use catalog::Catalog;
use error::{ApiError, ApiResult};
pub use limits::Limits;
use serde::Deserialize;
use serde_json::{json, Value};
use std::collections::HashMap;
use std::path::PathBuf;
use std::sync::Arc;
use tables::{lock, Tables};
use yokai_engine::{EpisodeRecord, Game, Replay, ReplayError, Seat};

#[derive(clap::Args)]
pub struct Args {
    /// Port to listen on (0: any free port, printed at start).
    #[arg(long, default_value_t = 8080)]
    port: u16,
    /// Address to listen on: 127.0.0.1 keeps the page on this machine; 0.0.0.0 opens it to
    /// the network (for a study on several computers; put a TLS proxy in front, see
    /// docs/play.md).
    #[arg(long, default_value = "127.0.0.1")]
    host: String,
    /// Default seats of a new game, seat 0 first: `human`, a built-in bot (`random`,
    /// `greedy`, `belief`, with parameters if you like), a pretrained agent
    /// (`pretrained:quick/0`) or a trained policy's path. Missing
    /// seats get `belief`; several humans play hot-seat. Every seat named here is offered
    /// to the page by the name written here.
    #[arg(long, default_value = "human,belief")]
    seats: String,
    /// A folder of trained policies (run directories or .ykp files, up to three levels
    /// down) to offer to the page, each by its path relative to the folder.
    #[arg(long)]
    policies: Option<PathBuf>,
    /// Game configurations to offer beside the paper's presets: short names or TOML files;
    /// the first is the default. Repeat the option for several.
    #[arg(short, long = "config", default_value = "9c-2p-perfect")]
    configs: Vec<String>,
    /// Where every game is recorded: RECORDS/SESSION/GAME.jsonl.
    #[arg(long, default_value = "runs/human-games")]
    records: PathBuf,
    /// Do not serve: print the table of the finished games in --records (one row per
    /// session and seating, in the paper's metrics) and exit.
    #[arg(long)]
    report: bool,
    #[command(flatten)]
    limits: Limits,
}

const INDEX: &str = include_str!("assets/index.html");
const APP: &str = include_str!("assets/app.js");
const STYLE: &str = include_str!("assets/style.css");

pub fn run(args: Args) -> anyhow::Result<()> {
    if args.report {
        print!("{}", records::report(&args.records)?);
        return Ok(());
    }
    let default = yokai_engine::Config::resolve(&args.configs[0])
        .with_context(|| format!("--config {}", args.configs[0]))?;
    let seats = crate::play::seat_names(&args.seats, &default)?;
    // Every policy is loaded now: a bad file fails here, where the operator reads it.
    let catalog = Catalog::new(&args.configs, &seats, args.policies.as_deref())?;
    let tables = Tables::new(catalog, seats, args.records.clone(), args.limits)?;
    let runtime = tokio::runtime::Builder::new_multi_thread()
        .enable_all()
        .build()
        .context("cannot start the server's runtime")?;
    runtime.block_on(async move {
        let listener = listen(&args.host, args.port)
            .await
            .with_context(|| format!("cannot listen on {}:{}", args.host, args.port))?;
        let address = listener.local_addr()?;
        eprintln!(
            "yokai serve: http://{address}/ ({default}, seats {}; records in {}; {} unfinished games)",
            tables.default_seats().join(", "),
            args.records.display(),
            tables.sessions.open_games(),
        );
        axum::serve(listener, router(Arc::new(tables)))
            .with_graceful_shutdown(async {
                let _ = tokio::signal::ctrl_c().await;
            })
            .await
            .context("the server stopped")
    })
}

/// How many connections the kernel may hold waiting for `accept` (capped by
/// `net.core.somaxconn`). Tokio's `bind` asks for 128, the standard library's value: when a
/// study's browsers (or the load test's 500 clients) connect at once while the server's two
/// cores are busy, the queue overflows and, with SYN cookies on, the kernel answers the
/// overflowing connections' first request with a reset.
const ACCEPT_BACKLOG: u32 = 4096;

/// A listener on the first address `host` resolves to that accepts, with room for
/// [`ACCEPT_BACKLOG`] connections waiting.
async fn listen(host: &str, port: u16) -> std::io::Result<tokio::net::TcpListener> {
    let mut last = None;
    for address in tokio::net::lookup_host((host, port)).await? {
        let socket = if address.is_ipv4() {
            tokio::net::TcpSocket::new_v4()?
        } else {
            tokio::net::TcpSocket::new_v6()?
        };
        // As tokio's `bind`: a restarted server can listen again at once (not on Windows,
        // where the option lets another process take the port).
        if cfg!(not(windows)) {
            socket.set_reuseaddr(true)?;
        }
        match socket
            .bind(address)
            .and_then(|()| socket.listen(ACCEPT_BACKLOG))
        {
            Ok(listener) => return Ok(listener),
            Err(e) => last = Some(e),
        }
    }
    Err(last.unwrap_or_else(|| {
        std::io::Error::new(
            std::io::ErrorKind::NotFound,
            "the host resolves to no address",
        )
    }))
}

/// The page and the API over `tables`.
pub fn router(tables: Arc<Tables>) -> Router {
    let asset = |kind: &'static str, body: &'static str| {
        get(move || async move { ([(header::CONTENT_TYPE, kind)], body) })
    };
    let max_body = tables.limits().max_body;
    Router::new()
        .route("/", asset("text/html; charset=utf-8", INDEX))
        .route("/app.js", asset("text/javascript; charset=utf-8", APP))
        .route("/style.css", asset("text/css; charset=utf-8", STYLE))
        .route("/api/config", get(config_handler))
        .route("/api/sessions", post(session_handler))
        .route("/api/games", post(create_handler))
        .route("/api/games/{id}", get(game_handler))
        .route("/api/games/{id}/actions", post(action_handler))
        .route("/api/games/{id}/reveal", post(reveal_handler))
        .route("/api/games/{id}/replay", get(replay_handler))
        .route("/api/replay", post(replay_view_handler))
        .route("/api/summary", get(summary_handler))
        .fallback(|| async { ApiError::NotFound("no such page".into()) })
        .layer(DefaultBodyLimit::max(max_body))
        .with_state(tables)
}

type Api = ApiResult<Json<Value>>;

/// A request's body as text, or why not (too large: `--max-body`).
fn body_text(body: Result<String, StringRejection>, tables: &Tables) -> ApiResult<String> {
    body.map_err(|rejection| {
        if rejection.status() == StatusCode::PAYLOAD_TOO_LARGE {
            ApiError::TooLarge(format!(
                "the request is larger than {} bytes, the server's --max-body",
                tables.limits().max_body
            ))
        } else {
            ApiError::BadRequest("the request body is not UTF-8 text".into())
        }
    })
}

/// A JSON body, or an error that says what is wrong with it.
fn parse<T: for<'de> Deserialize<'de>>(
    body: Result<String, StringRejection>,
    tables: &Tables,
) -> ApiResult<T> {
    let text = body_text(body, tables)?;
    serde_json::from_str(&text)
        .map_err(|e| ApiError::BadRequest(format!("the request is not valid: {e}")))
}

/// The query string's fields.
fn query(
    q: Result<Query<HashMap<String, String>>, QueryRejection>,
) -> ApiResult<HashMap<String, String>> {
    q.map(|Query(q)| q)
        .map_err(|_| ApiError::BadRequest("the query string is not valid".into()))
}

/// The game id in the path.
fn game_id(id: Result<UrlPath<String>, PathRejection>) -> ApiResult<String> {
    id.map(|UrlPath(id)| id)
        .map_err(|_| ApiError::NotFound("no such game in this session".into()))
}

/// Run `work` off the async threads (it may let bots think, read a record, or wait for a
/// game whose bots are thinking).
async fn off_thread<T: Send + 'static>(
    work: impl FnOnce() -> ApiResult<T> + Send + 'static,
) -> ApiResult<T> {
    tokio::task::spawn_blocking(work)
        .await
        .map_err(|e| ApiError::Internal(anyhow::anyhow!("a request's task failed: {e}")))?
}

/// [`off_thread`] for work whose answer is JSON.
async fn blocking(work: impl FnOnce() -> ApiResult<Value> + Send + 'static) -> Api {
    off_thread(work).await.map(Json)
}

async fn config_handler(State(tables): State<Arc<Tables>>) -> Json<Value> {
    let catalog = tables.catalog();
    let config = catalog.default_config();
    Json(json!({
        "config": config.to_string(),
        "seats": tables.default_seats(),
        "players": config.players(),
        "offered": { "configs": catalog.config_names(), "seats": catalog.seat_names() },
    }))
}

async fn session_handler(State(tables): State<Arc<Tables>>) -> Api {
    Ok(Json(json!({ "session": tables.sessions.issue()? })))
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct NewGame {
    session: String,
    config: Option<String>,
    seats: Option<Vec<String>>,
    seed: Option<u64>,
}

async fn create_handler(
    State(tables): State<Arc<Tables>>,
    body: Result<String, StringRejection>,
) -> Api {
    let req: NewGame = parse(body, &tables)?;
    blocking(move || {
        let t = tables.create(&req.session, req.config.as_deref(), req.seats, req.seed)?;
        let json = game_json(&lock(&t), 0);
        Ok(json)
    })
    .await
}

async fn game_handler(
    State(tables): State<Arc<Tables>>,
    id: Result<UrlPath<String>, PathRejection>,
    q: Result<Query<HashMap<String, String>>, QueryRejection>,
) -> Api {
    let (id, q) = (game_id(id)?, query(q)?);
    let session = q.get("session").cloned().unwrap_or_default();
    let since = match q.get("since") {
        Some(k) => k.parse::<usize>().map_err(|_| {
            ApiError::BadRequest(format!("since {} is not a step number", error::quoted(k)))
        })?,
        None => usize::MAX,
    };
    // Reading a record back, or waiting for a game whose bots think: off the async threads.
    blocking(move || {
        let table = tables.get(&session, &id)?;
        let json = game_json(&lock(&table), since);
        Ok(json)
    })
    .await
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct Act {
    session: String,
    seat: u8,
    action: usize,
}

async fn action_handler(
    State(tables): State<Arc<Tables>>,
    id: Result<UrlPath<String>, PathRejection>,
    body: Result<String, StringRejection>,
) -> Api {
    let id = game_id(id)?;
    let req: Act = parse(body, &tables)?;
    // Bots (a trained network, the belief bot) may think for a while: off the async threads.
    blocking(move || {
        let table = tables.get(&req.session, &id)?;
        let mut t = lock(&table);
        let before = t.session.game().steps();
        tables.act(&mut t, req.seat, req.action)?;
        Ok(game_json(&t, before))
    })
    .await
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct Reveal {
    session: String,
}

async fn reveal_handler(
    State(tables): State<Arc<Tables>>,
    id: Result<UrlPath<String>, PathRejection>,
    body: Result<String, StringRejection>,
) -> Api {
    let id = game_id(id)?;
    let req: Reveal = parse(body, &tables)?;
    blocking(move || {
        let table = tables.get(&req.session, &id)?;
        let mut t = lock(&table);
        if t.session.curtain() {
            t.session.handle(crate::play::session::Key::Enter)?;
        }
        Ok(game_json(&t, usize::MAX))
    })
    .await
}

async fn replay_handler(
    State(tables): State<Arc<Tables>>,
    id: Result<UrlPath<String>, PathRejection>,
    q: Result<Query<HashMap<String, String>>, QueryRejection>,
) -> Result<Response, ApiError> {
    let (id, q) = (game_id(id)?, query(q)?);
    let session = q.get("session").cloned().unwrap_or_default();
    let text = off_thread(move || {
        let table = tables.get(&session, &id)?;
        let text = lock(&table).session.replay().to_jsonl();
        Ok(text)
    })
    .await?;
    Ok((
        [(header::CONTENT_TYPE, "application/jsonl; charset=utf-8")],
        text,
    )
        .into_response())
}

async fn replay_view_handler(
    State(tables): State<Arc<Tables>>,
    body: Result<String, StringRejection>,
) -> Api {
    let text = body_text(body, &tables)?;
    // The client's own text is parsed: an error may quote it, never a file.
    let not_replay = |e: &dyn std::fmt::Display| {
        let message: String = e.to_string().chars().take(200).collect();
        ApiError::BadRequest(format!("not a replay: {message}"))
    };
    blocking(move || {
        let replay = Replay::from_jsonl(&text).map_err(|e| not_replay(&e))?;
        // Every board with all colours shown: a replay is watched after the fact.
        let frames =
            boards_after(&replay.record(), 0, view::truth_view).map_err(|e| not_replay(&e))?;
        Ok(json!({
            "config": replay.header.config.to_string(),
            "seats": replay.header.seats,
            "steps": replay.steps.iter().map(|s| json!({"seat": s.seat, "name": s.name})).collect::<Vec<_>>(),
            "frames": frames,
            "outcome": replay.outcome,
        }))
    })
    .await
}

async fn summary_handler(
    State(tables): State<Arc<Tables>>,
    q: Result<Query<HashMap<String, String>>, QueryRejection>,
) -> Api {
    let session = query(q)?.get("session").cloned().unwrap_or_default();
    blocking(move || tables.summary(&session)).await
}

/// The game as the page needs it: seats, whose view (the acting human, else the last
/// human), the curtain, the log, the board, and the boards after every step since `since`.
fn game_json(t: &tables::Table, since: usize) -> Value {
    let s = &t.session;
    let viewer = s.viewer();
    let curtain = s.curtain();
    let board = (!curtain).then(|| view::seat_view(s.game(), viewer));
    let steps = s.game().steps();
    let frames = if curtain || since >= steps {
        Vec::new()
    } else {
        // The viewer's board after each step since `since` (a game is a few dozen steps).
        boards_after(s.record(), since + 1, |g| view::seat_view(g, viewer))
            .expect("a game played through the rules replays")
    };
    json!({
        "id": t.id,
        "session": t.session_id,
        "seed": t.seed,
        "config": s.game().config().to_string(),
        "seats": s.names(),
        "humans": (0..s.names().len()).filter(|&i| s.is_human(Seat(i as u8))).collect::<Vec<_>>(),
        "viewer": viewer.0,
        "to_act": s.human_to_act().map(|x| x.0),
        "curtain": curtain,
        "log": s.log(),
        "board": board,
        "frames": frames,
    })
}

/// `board(game)` of the game after each step from `first` (0: the deal) to the end.
fn boards_after(
    record: &EpisodeRecord,
    first: usize,
    board: impl Fn(&Game) -> Value,
) -> Result<Vec<Value>, ReplayError> {
    let mut out = Vec::new();
    let mut step = 0;
    // `replay_with` shows the game before each action: the game after `step` steps.
    let end = record.replay_with(|before, _, _| {
        if step >= first {
            out.push(board(before));
        }
        step += 1;
    })?;
    if step >= first {
        out.push(board(&end));
    }
    Ok(out)
}
