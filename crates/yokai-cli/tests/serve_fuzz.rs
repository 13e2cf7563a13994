//! `yokai serve` fed arbitrary requests (proptest over the HTTP API): paths of files on the
//! server, other strings, valid and invalid ids, malformed and oversized JSON, at every
//! endpoint. No answer may carry a line of a file the client named (a planted secret, a
//! planted game config, /etc/passwd), no answer may be a 500, and the server keeps
//! serving.

#[path = "common/server.rs"]
mod server;

use proptest::prelude::*;
use serde_json::{json, Value};
use server::{id, tempdir, Server};

/// Percent-encode `text` for a URL's path segment or query value.
fn encode(text: &str) -> String {
    text.bytes()
        .map(|b| match b {
            b'A'..=b'Z' | b'a'..=b'z' | b'0'..=b'9' | b'-' | b'_' | b'.' | b'~' => {
                (b as char).to_string()
            }
            _ => format!("%{b:02X}"),
        })
        .collect()
}

/// One request: method, path (already encoded), body.
#[derive(Debug, Clone)]
struct Request {
    method: &'static str,
    path: String,
    body: String,
}

/// The planted files and the ids a client may know.
struct World {
    files: Vec<String>,
    session: String,
    game: String,
}

fn a_string(world: &World) -> BoxedStrategy<String> {
    let known: Vec<String> = world
        .files
        .iter()
        .cloned()
        .chain([world.session.clone(), world.game.clone()])
        .chain(
            [
                "human",
                "belief",
                "9c-2p",
                "../../etc/passwd",
                "..",
                "/",
                "%2e%2e",
                "",
            ]
            .map(String::from),
        )
        .collect();
    prop_oneof![
        3 => proptest::sample::select(known),
        2 => "\\PC{0,40}",
        1 => "[0-9a-f]{16}|[0-9a-f]{32}",
        1 => proptest::sample::select(world.files.clone()).prop_map(|f| format!("{f}.toml")),
    ]
    .boxed()
}

fn a_value(world: &World) -> BoxedStrategy<Value> {
    let s = a_string(world);
    prop_oneof![
        s.clone().prop_map(Value::from),
        any::<i64>().prop_map(Value::from),
        proptest::collection::vec(s, 0..5).prop_map(Value::from),
        Just(Value::Null),
    ]
    .boxed()
}

fn a_body(world: &World) -> BoxedStrategy<String> {
    let fields = proptest::collection::btree_map(
        proptest::sample::select(vec![
            "session", "config", "seats", "seed", "seat", "action", "x",
        ]),
        a_value(world),
        0..6,
    );
    let session = world.session.clone();
    prop_oneof![
        4 => (fields, any::<bool>()).prop_map(move |(f, with_session)| {
            let mut o: serde_json::Map<String, Value> =
                f.into_iter().map(|(k, v)| (k.to_string(), v)).collect();
            if with_session {
                o.insert("session".into(), Value::from(session.clone()));
            }
            Value::Object(o).to_string()
        }),
        1 => "\\PC{0,60}",
        1 => a_string(world).prop_map(|s| format!("{{\"session\": \"{s}\", \"seats\": [")),
        1 => Just(format!("{{\"config\": \"{}\"}}", "y".repeat(5000))),
    ]
    .boxed()
}

fn a_request(world: &World) -> BoxedStrategy<Request> {
    let s = || a_string(world);
    let body = a_body(world);
    prop_oneof![
        (s(), s(), s()).prop_map(|(g, q, k)| Request {
            method: "GET",
            path: format!(
                "/api/games/{}?session={}&since={}",
                encode(&g),
                encode(&q),
                encode(&k)
            ),
            body: String::new(),
        }),
        (s(), s()).prop_map(|(g, q)| Request {
            method: "GET",
            path: format!("/api/games/{}/replay?session={}", encode(&g), encode(&q)),
            body: String::new(),
        }),
        s().prop_map(|q| Request {
            method: "GET",
            path: format!("/api/summary?session={}", encode(&q)),
            body: String::new(),
        }),
        s().prop_map(|p| Request {
            method: "GET",
            path: format!("/{}", encode(&p)),
            body: String::new(),
        }),
        body.clone().prop_map(|b| Request {
            method: "POST",
            path: "/api/games".into(),
            body: b,
        }),
        (
            s(),
            body.clone(),
            proptest::sample::select(vec!["actions", "reveal"])
        )
            .prop_map(|(g, b, what)| Request {
                method: "POST",
                path: format!("/api/games/{}/{what}", encode(&g)),
                body: b,
            }),
        body.prop_map(|b| Request {
            method: "POST",
            path: "/api/replay".into(),
            body: b,
        }),
    ]
    .boxed()
}

/// The status and text of the answer to `r`.
fn send(server: &Server, r: &Request) -> (u16, String) {
    let url = format!("{}{}", server.base, r.path);
    let sent = match r.method {
        "GET" => ureq::get(&url).call(),
        _ => ureq::post(&url).send_string(&r.body),
    };
    match sent {
        Ok(res) => (res.status(), res.into_string().unwrap()),
        Err(ureq::Error::Status(code, res)) => (code, res.into_string().unwrap_or_default()),
        Err(e) => panic!("{r:?}: the server did not answer: {e}"),
    }
}

#[test]
fn no_request_reads_out_a_file_or_breaks_the_server() {
    let tmp = tempdir();
    let secret = tmp.path().join("secret.toml");
    std::fs::write(
        &secret,
        "api_key = \"SECRET-7f3a9c2e\"\n[database]\npassword = \"correct-horse-battery\"\n",
    )
    .unwrap();
    // A valid game config: the old server would have played it (and named it).
    let planted = tmp.path().join("planted.toml");
    std::fs::write(&planted, "# planted-config-comment\ncards = 9\ncolours = 3\ngrid = 9\nplayers = 2\nhints = [2, 3, 2]\n").unwrap();
    let mut server = Server::start(
        &tmp.path().join("records"),
        "human,random",
        &["--max-body", "4096"],
    );
    let session = server.session();
    let game = server.new_game(&session, json!({}));
    let world = World {
        files: vec![
            secret.display().to_string(),
            planted.display().to_string(),
            tmp.path().display().to_string(),
            "/etc/passwd".into(),
            "/etc/hostname".into(),
        ],
        session,
        game: id(&game).to_string(),
    };
    // Every line of every named file that is long enough not to appear by chance.
    let mut lines: Vec<String> = Vec::new();
    for f in &world.files {
        if let Ok(text) = std::fs::read_to_string(f) {
            lines.extend(text.lines().filter(|l| l.len() >= 8).map(String::from));
        }
    }
    assert!(lines.iter().any(|l| l.contains("SECRET-7f3a9c2e")));
    let mut runner = proptest::test_runner::TestRunner::new(ProptestConfig {
        cases: 2000,
        failure_persistence: None,
        ..ProptestConfig::default()
    });
    let statuses = std::cell::RefCell::new(std::collections::BTreeMap::<u16, usize>::new());
    runner
        .run(&a_request(&world), |r| {
            let (status, text) = send(&server, &r);
            *statuses.borrow_mut().entry(status).or_default() += 1;
            prop_assert!(status != 500, "{r:?} -> {status} {text}");
            for line in &lines {
                prop_assert!(
                    !text.contains(line.as_str()),
                    "{r:?} -> {text} holds `{line}`"
                );
            }
            prop_assert!(
                !text.contains("SECRET") && !text.contains("correct-horse"),
                "{r:?} -> {text}"
            );
            let (alive, _) = send(
                &server,
                &Request {
                    method: "GET",
                    path: "/api/config".into(),
                    body: String::new(),
                },
            );
            prop_assert_eq!(alive, 200);
            Ok(())
        })
        .unwrap();
    assert!(server.alive());
    let statuses = statuses.into_inner();
    eprintln!("answers by status: {statuses:?}");
    // The fuzz reached the deep ends: games were made, actions refused, and sizes refused.
    for code in [200, 400, 403, 404, 413] {
        assert!(statuses.contains_key(&code), "no {code} among {statuses:?}");
    }
}
