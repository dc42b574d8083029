//! Headless Chromium driven through the DevTools protocol over a pipe (`--remote-debugging-pipe`:
//! JSON messages ended by a NUL byte, commands on the browser's fd 3, answers and events on its
//! fd 4): open a page, evaluate script in it, take screenshots, and collect what it reported as
//! errors (exceptions, `console.error`, failed loads and blocked ones).

use serde_json::{json, Value};
use std::io::{BufRead, BufReader, Write};
use std::path::{Path, PathBuf};
use std::process::{Child, ChildStdin, Command, Stdio};
use std::sync::mpsc::{channel, Receiver};
use std::time::Duration;

/// How long an answer may take.
const ANSWER: Duration = Duration::from_secs(30);

/// The Chromium executable on PATH; a test that needs it fails without it, saying how to
/// install it.
pub fn chromium() -> PathBuf {
    let path = std::env::var_os("PATH").unwrap_or_default();
    std::env::split_paths(&path)
        .map(|dir| dir.join("chromium"))
        .find(|file| file.is_file())
        .expect(
            "this test renders a page in headless Chromium, which is not installed: install \
             Debian's `chromium` package (`apt-get install chromium`) or run `bash .ci/setup`",
        )
}

/// A headless Chromium with one page open, attached to it.
pub struct Browser {
    child: Child,
    commands: ChildStdin,
    messages: Receiver<Value>,
    last_id: u64,
    session: String,
    /// The events received so far, oldest first.
    pub events: Vec<Value>,
}

impl Browser {
    /// Starts Chromium with its profile in `profile` and a window of `width` x `height` px, and
    /// opens a blank page with its runtime, log and page events on.
    pub fn start(profile: &Path, width: u32, height: u32) -> Browser {
        // The shell hands our pipes to Chromium as fds 3 and 4.
        let mut child = Command::new("sh")
            .arg("-c")
            .arg(r#"exec "$0" "$@" 3<&0 4>&1 0</dev/null 1>/dev/null"#)
            .arg(chromium())
            .args([
                "--headless",
                "--no-sandbox",
                "--disable-gpu",
                "--hide-scrollbars",
            ])
            .arg("--remote-debugging-pipe")
            .arg(format!("--user-data-dir={}", profile.display()))
            .arg(format!("--window-size={width},{height}"))
            .stdin(Stdio::piped())
            .stdout(Stdio::piped())
            .stderr(Stdio::null())
            .spawn()
            .expect("chromium starts");
        let commands = child.stdin.take().unwrap();
        let mut answers = BufReader::new(child.stdout.take().unwrap());
        let (sender, messages) = channel();
        std::thread::spawn(move || loop {
            let mut message = Vec::new();
            match answers.read_until(0, &mut message) {
                Ok(n) if n > 0 && message.pop() == Some(0) => {
                    let value = serde_json::from_slice(&message).expect("a JSON message");
                    if sender.send(value).is_err() {
                        return;
                    }
                }
                _ => return,
            }
        });
        let mut browser = Browser {
            child,
            commands,
            messages,
            last_id: 0,
            session: String::new(),
            events: Vec::new(),
        };
        let target = browser.send("Target.createTarget", json!({ "url": "about:blank" }));
        let attached = browser.send(
            "Target.attachToTarget",
            json!({ "targetId": target["targetId"], "flatten": true }),
        );
        browser.session = attached["sessionId"].as_str().unwrap().to_owned();
        for domain in ["Runtime", "Log", "Page"] {
            browser.send(&format!("{domain}.enable"), json!({}));
        }
        browser
    }

    /// Sends a command (to the page once attached) and waits for its result; panics on an
    /// error or when none comes.
    pub fn send(&mut self, method: &str, params: Value) -> Value {
        self.last_id += 1;
        let mut command = json!({ "id": self.last_id, "method": method, "params": params });
        if !self.session.is_empty() {
            command["sessionId"] = self.session.clone().into();
        }
        let mut bytes = serde_json::to_vec(&command).unwrap();
        bytes.push(0);
        self.commands.write_all(&bytes).expect("chromium reads");
        loop {
            let message = self.next(method);
            if message["id"] == self.last_id {
                assert!(message["error"].is_null(), "{method}: {message}");
                return message["result"].clone();
            }
            self.events.push(message);
        }
    }

    /// The next message, waiting for the answer to `method`.
    fn next(&mut self, method: &str) -> Value {
        self.messages
            .recv_timeout(ANSWER)
            .unwrap_or_else(|e| panic!("chromium sent nothing after {method}: {e}"))
    }

    /// Opens `file` and waits until it has loaded, with every image.
    pub fn open(&mut self, file: &Path) {
        let url = format!("file://{}", file.display());
        let seen = self.events.len();
        self.send("Page.navigate", json!({ "url": url }));
        let loaded = |e: &Value| e["method"] == "Page.loadEventFired";
        while !self.events[seen..].iter().any(loaded) {
            let message = self.next("Page.navigate");
            self.events.push(message);
        }
    }

    /// The value of `expression` evaluated in the page.
    pub fn evaluate(&mut self, expression: &str) -> Value {
        let result = self.send(
            "Runtime.evaluate",
            json!({ "expression": expression, "returnByValue": true }),
        );
        assert!(
            result["exceptionDetails"].is_null(),
            "{expression}: {result}"
        );
        result["result"]["value"].clone()
    }

    /// A PNG (in base64) of the page's region `clip` (`x`, `y`, `width`, `height` in CSS px).
    pub fn screenshot(&mut self, clip: &Value) -> String {
        let mut clip = clip.clone();
        clip["scale"] = 1.into();
        let shot = self.send(
            "Page.captureScreenshot",
            json!({ "format": "png", "clip": clip, "captureBeyondViewport": true }),
        );
        shot["data"].as_str().unwrap().to_owned()
    }

    /// What the page reported as errors: uncaught exceptions, `console.error` and
    /// `console.assert`, and the log's errors (a resource that failed to load, one the
    /// content security policy blocked).
    pub fn errors(&self) -> Vec<String> {
        let mut errors = Vec::new();
        for event in &self.events {
            let params = &event["params"];
            let error = match event["method"].as_str() {
                Some("Runtime.exceptionThrown") => true,
                Some("Runtime.consoleAPICalled") => {
                    matches!(params["type"].as_str(), Some("error" | "assert"))
                }
                Some("Log.entryAdded") => params["entry"]["level"] == "error",
                _ => false,
            };
            if error {
                errors.push(params.to_string());
            }
        }
        errors
    }
}

impl Drop for Browser {
    /// Closes the browser, and kills it if it has not exited within a few seconds.
    fn drop(&mut self) {
        self.session.clear();
        let _ = self
            .commands
            .write_all(b"{\"id\":0,\"method\":\"Browser.close\"}\0");
        for _ in 0..50 {
            if let Ok(Some(_)) = self.child.try_wait() {
                return;
            }
            std::thread::sleep(Duration::from_millis(100));
        }
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}
