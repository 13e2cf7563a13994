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
//! API (JSON; `session` is the browser's id, under which its games are filed):
//! - `GET  /api/config`: the server's default game and seats;
//! - `POST /api/games` `{session, config?, seats?, seed?}`: a new game;
//! - `GET  /api/games/{id}?session=S&since=K`: the game, with the boards after each step
//!   since step K (to show the bots' moves one at a time);
//! - `POST /api/games/{id}/actions` `{session, seat, action}`: play an action index;
//! - `POST /api/games/{id}/reveal` `{session}`: lift the hot-seat curtain;
//! - `GET  /api/games/{id}/replay?session=S`: the record as replay JSONL;
//! - `POST /api/replay` (replay JSONL): every board of a replay, all colours shown;
//! - `GET  /api/summary?session=S`: R, SEE, EE, WEE, LEN over the session's finished games.

mod tables;
mod view;

use anyhow::Context;
use axum::extract::{Path as UrlPath, Query, State};
use axum::http::{header, StatusCode};
use axum::response::{IntoResponse, Response};
use axum::routing::{get, post};
use axum::{Json, Router};
use serde::Deserialize;
use serde_json::{json, Value};
use std::collections::HashMap;
use std::path::PathBuf;
use std::sync::Arc;
pub use tables::{Defaults, Tables};
use yokai_engine::{Config, EpisodeRecord, Game, Replay, ReplayError, Seat};

#[derive(clap::Args)]
pub struct Args {
    /// Port to listen on (0: any free port, printed at start).
    #[arg(long, default_value_t = 8080)]
    port: u16,
    /// Address to listen on: 127.0.0.1 keeps the page on this machine; 0.0.0.0 opens it to
    /// the network (for a study on several computers).
    #[arg(long, default_value = "127.0.0.1")]
    host: String,
    /// Default seats of a new game, seat 0 first: `human`, a built-in policy (`random`,
    /// `greedy`, `belief`) or a trained policy's path. Missing seats get `belief`; several
    /// humans play hot-seat. The page can ask for others.
    #[arg(long, default_value = "human,belief")]
    seats: String,
    /// Default game configuration: a short name or a TOML file.
    #[arg(short, long, default_value = "9c-2p-perfect")]
    config: String,
    /// Where every game is recorded: RECORDS/SESSION/GAME.jsonl.
    #[arg(long, default_value = "runs/human-games")]
    records: PathBuf,
    /// Do not serve: print the table of the finished games in --records (one row per
    /// session and seating, in the paper's metrics) and exit.
    #[arg(long)]
    report: bool,
}

const INDEX: &str = include_str!("assets/index.html");
const APP: &str = include_str!("assets/app.js");
const STYLE: &str = include_str!("assets/style.css");

pub fn run(args: Args) -> anyhow::Result<()> {
    if args.report {
        print!("{}", tables::report(&args.records)?);
        return Ok(());
    }
    let config = Config::resolve(&args.config)?;
    let seats = crate::play::seat_names(&args.seats, &config)?;
    // Seat every default once now, so a bad policy path fails here, not in the page.
    let tables = Tables::new(Defaults { config, seats }, args.records.clone());
    tables.check_defaults()?;
    let runtime = tokio::runtime::Builder::new_multi_thread()
        .enable_all()
        .build()
        .context("cannot start the server's runtime")?;
    runtime.block_on(async move {
        let listener = tokio::net::TcpListener::bind((args.host.as_str(), args.port))
            .await
            .with_context(|| format!("cannot listen on {}:{}", args.host, args.port))?;
        let address = listener.local_addr()?;
        eprintln!(
            "yokai serve: http://{address}/ ({config}, seats {}; records in {})",
            tables.defaults().seats.join(", "),
            args.records.display()
        );
        axum::serve(listener, router(Arc::new(tables)))
            .with_graceful_shutdown(async {
                let _ = tokio::signal::ctrl_c().await;
            })
            .await
            .context("the server stopped")
    })
}

/// The page and the API over `tables`.
pub fn router(tables: Arc<Tables>) -> Router {
    let asset = |kind: &'static str, body: &'static str| {
        get(move || async move { ([(header::CONTENT_TYPE, kind)], body) })
    };
    Router::new()
        .route("/", asset("text/html; charset=utf-8", INDEX))
        .route("/app.js", asset("text/javascript; charset=utf-8", APP))
        .route("/style.css", asset("text/css; charset=utf-8", STYLE))
        .route("/api/config", get(config_handler))
        .route("/api/games", post(create_handler))
        .route("/api/games/{id}", get(game_handler))
        .route("/api/games/{id}/actions", post(action_handler))
        .route("/api/games/{id}/reveal", post(reveal_handler))
        .route("/api/games/{id}/replay", get(replay_handler))
        .route("/api/replay", post(replay_view_handler))
        .route("/api/summary", get(summary_handler))
        .with_state(tables)
}

/// An error as the page sees it: `{"error": message}` with a status.
struct ApiError(StatusCode, String);

impl IntoResponse for ApiError {
    fn into_response(self) -> Response {
        eprintln!("yokai serve: refused ({}): {}", self.0.as_u16(), self.1);
        (self.0, Json(json!({ "error": self.1 }))).into_response()
    }
}

fn bad(e: anyhow::Error) -> ApiError {
    ApiError(StatusCode::BAD_REQUEST, format!("{e:#}"))
}

fn not_found(e: anyhow::Error) -> ApiError {
    ApiError(StatusCode::NOT_FOUND, format!("{e:#}"))
}

/// A JSON body, or an error that says what is wrong with it.
fn parse<T: for<'de> Deserialize<'de>>(body: &str) -> Result<T, ApiError> {
    serde_json::from_str(body).map_err(|e| bad(anyhow::anyhow!("the request is not valid: {e}")))
}

type Api = Result<Json<Value>, ApiError>;

/// Run `work` off the async threads (it may load a network, let bots think, or wait for a
/// game whose bots are thinking); its error becomes a 400 answer.
async fn blocking(work: impl FnOnce() -> anyhow::Result<Value> + Send + 'static) -> Api {
    match tokio::task::spawn_blocking(work).await {
        Ok(out) => out.map(Json).map_err(bad),
        Err(e) => Err(bad(anyhow::anyhow!("the request could not be served: {e}"))),
    }
}

async fn config_handler(State(tables): State<Arc<Tables>>) -> Json<Value> {
    let d = tables.defaults();
    Json(json!({ "config": d.config.to_string(), "seats": d.seats, "players": d.config.players() }))
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct NewGame {
    session: String,
    config: Option<String>,
    seats: Option<Vec<String>>,
    seed: Option<u64>,
}

async fn create_handler(State(tables): State<Arc<Tables>>, body: String) -> Api {
    let req: NewGame = parse(&body)?;
    // Loading a trained policy reads a file: off the async threads.
    blocking(move || {
        let t = tables.create(&req.session, req.config.as_deref(), req.seats, req.seed)?;
        let json = game_json(&t.lock().unwrap_or_else(|e| e.into_inner()), 0);
        Ok(json)
    })
    .await
}

async fn game_handler(
    State(tables): State<Arc<Tables>>,
    UrlPath(id): UrlPath<String>,
    Query(q): Query<HashMap<String, String>>,
) -> Api {
    let session = q.get("session").cloned().unwrap_or_default();
    let since = match q.get("since") {
        Some(k) => k
            .parse::<usize>()
            .map_err(|_| bad(anyhow::anyhow!("since `{k}` is not a step number")))?,
        None => usize::MAX,
    };
    let table = tables.get(&session, &id).map_err(not_found)?;
    // The game's lock may be held while its bots think: wait for it off the async threads.
    blocking(move || {
        Ok(game_json(
            &table.lock().unwrap_or_else(|e| e.into_inner()),
            since,
        ))
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
    UrlPath(id): UrlPath<String>,
    body: String,
) -> Api {
    let req: Act = parse(&body)?;
    let table = tables.get(&req.session, &id).map_err(not_found)?;
    // Bots (a trained network, the belief bot) may think for a while: off the async threads.
    blocking(move || {
        let mut t = table.lock().unwrap_or_else(|e| e.into_inner());
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
    UrlPath(id): UrlPath<String>,
    body: String,
) -> Api {
    let req: Reveal = parse(&body)?;
    let table = tables.get(&req.session, &id).map_err(not_found)?;
    let mut t = table.lock().unwrap_or_else(|e| e.into_inner());
    if t.session.curtain() {
        t.session
            .handle(crate::play::session::Key::Enter)
            .map_err(bad)?;
    }
    Ok(Json(game_json(&t, usize::MAX)))
}

async fn replay_handler(
    State(tables): State<Arc<Tables>>,
    UrlPath(id): UrlPath<String>,
    Query(q): Query<HashMap<String, String>>,
) -> Result<Response, ApiError> {
    let session = q.get("session").cloned().unwrap_or_default();
    let table = tables.get(&session, &id).map_err(not_found)?;
    let text = table
        .lock()
        .unwrap_or_else(|e| e.into_inner())
        .session
        .replay()
        .to_jsonl();
    Ok((
        [(header::CONTENT_TYPE, "application/jsonl; charset=utf-8")],
        text,
    )
        .into_response())
}

async fn replay_view_handler(body: String) -> Api {
    let replay = Replay::from_jsonl(&body).map_err(|e| bad(anyhow::anyhow!("{e}")))?;
    // Every board with all colours shown: a replay is watched after the fact.
    let frames = boards_after(&replay.record(), 0, view::truth_view).map_err(|e| bad(e.into()))?;
    Ok(Json(json!({
        "config": replay.header.config.to_string(),
        "seats": replay.header.seats,
        "steps": replay.steps.iter().map(|s| json!({"seat": s.seat, "name": s.name})).collect::<Vec<_>>(),
        "frames": frames,
        "outcome": replay.outcome,
    })))
}

async fn summary_handler(
    State(tables): State<Arc<Tables>>,
    Query(q): Query<HashMap<String, String>>,
) -> Api {
    let session = q.get("session").cloned().unwrap_or_default();
    tables.summary(&session).map(Json).map_err(bad)
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
