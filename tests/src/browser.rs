//! A real headless Chromium (Debian's `chromium`) driven through `chromedriver` over WebDriver.
//!
//! Each [`Browser`] runs its own chromedriver on a free port, in its own process group, and
//! ends that whole group (driver and every browser it started) when dropped, even after a
//! failed assertion. Each [`Session`] is a separate browser with a fresh profile, so two
//! sessions are two caretakers.

use std::net::TcpListener;
use std::os::unix::process::CommandExt;
use std::path::PathBuf;
use std::process::{Child, Command, Stdio};

use fantoccini::elements::Element;
use fantoccini::{Client, ClientBuilder, Locator};
use hyper_util::client::legacy::connect::HttpConnector;
use serde_json::{Value, json};
use tempfile::TempDir;

use pps_test_kit::{target_dir, wait};

/// A phone's width (CSS pixels), the narrowest screen the UI supports.
pub const PHONE: (u32, u32) = (375, 812);
/// A laptop's window.
pub const DESKTOP: (u32, u32) = (1280, 900);

/// What headless Chromium needs as root on a CI machine, without reaching out anywhere.
const CHROMIUM_FLAGS: [&str; 9] = [
    "--headless",
    "--no-sandbox",
    "--disable-gpu",
    "--disable-background-networking",
    "--disable-component-update",
    "--disable-sync",
    "--no-first-run",
    "--disable-dev-shm-usage",
    "--hide-scrollbars",
];

fn find_program(env: &str, names: &[&str]) -> PathBuf {
    if let Some(path) = std::env::var_os(env) {
        return PathBuf::from(path);
    }
    let dirs: Vec<PathBuf> = std::env::var_os("PATH")
        .map(|path| std::env::split_paths(&path).collect())
        .unwrap_or_default();
    names
        .iter()
        .flat_map(|name| dirs.iter().map(move |dir| dir.join(name)))
        .find(|path| path.is_file())
        .unwrap_or_else(|| {
            panic!(
                "{} not found on PATH (or set {env}); install Debian's chromium and \
                 chromium-driver packages, as tests/run does",
                names.join(" or ")
            )
        })
}

/// A chromedriver process and the browsers it starts.
#[derive(Debug)]
pub struct Browser {
    driver: Child,
    url: String,
    chromium: PathBuf,
}

impl Browser {
    /// Starts chromedriver on a free port and waits until it answers.
    pub async fn start() -> Self {
        let chromium = find_program("CHROMIUM", &["chromium", "chromium-browser"]);
        let chromedriver = find_program("CHROMEDRIVER", &["chromedriver"]);
        let port = TcpListener::bind("127.0.0.1:0")
            .and_then(|listener| listener.local_addr())
            .expect("a free port")
            .port();
        let driver = Command::new(&chromedriver)
            .arg(format!("--port={port}"))
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            // Its own process group, so dropping the Browser ends the browsers it started too.
            .process_group(0)
            .spawn()
            .unwrap_or_else(|e| panic!("cannot start {}: {e}", chromedriver.display()));
        let url = format!("http://127.0.0.1:{port}");
        let status = format!("{url}/status");
        let http = reqwest::Client::new();
        wait::until("chromedriver to answer", || async {
            let response = http.get(&status).send().await.ok()?;
            response.status().is_success().then_some(())
        })
        .await;
        Self { driver, url, chromium }
    }

    /// A new browser window of `size` (CSS pixels) with a fresh profile, pointed at `base`.
    pub async fn session(&self, base: &str, size: (u32, u32)) -> Session {
        let profile = tempfile::tempdir().expect("a temporary profile directory");
        let mut args: Vec<String> = CHROMIUM_FLAGS.iter().map(|flag| (*flag).to_owned()).collect();
        args.push(format!("--user-data-dir={}", profile.path().display()));
        args.push(format!("--window-size={},{}", size.0, size.1));
        let capabilities = json!({
            "browserName": "chrome",
            "goog:chromeOptions": { "binary": self.chromium, "args": args },
        });
        let Value::Object(capabilities) = capabilities else { unreachable!("an object") };
        let client = ClientBuilder::new(HttpConnector::new())
            .capabilities(capabilities)
            .connect(&self.url)
            .await
            .unwrap_or_else(|e| panic!("Chromium did not start under chromedriver: {e}"));
        let session = Session { client, base: base.to_owned(), _profile: profile };
        session.set_viewport(size).await;
        session
    }
}

impl Drop for Browser {
    fn drop(&mut self) {
        // The driver's process group: chromedriver and every Chromium process it started.
        let _ = Command::new("kill")
            .args(["-KILL", "--", &format!("-{}", self.driver.id())])
            .stderr(Stdio::null())
            .status();
        let _ = self.driver.wait();
    }
}

/// One browser window: a caretaker at their phone or laptop.
#[derive(Debug)]
pub struct Session {
    pub client: Client,
    base: String,
    _profile: TempDir,
}

impl Session {
    /// Opens a path of the registry, e.g. `/` or `/#/robots`.
    pub async fn open(&self, path: &str) {
        self.client.goto(&format!("{}{path}", self.base)).await.expect("navigation");
    }

    /// Makes the page's viewport exactly `size` CSS pixels, whatever the window decorations.
    pub async fn set_viewport(&self, (width, height): (u32, u32)) {
        self.client.set_window_size(width, height).await.expect("window resized");
        let inner = self.eval("return [window.innerWidth, window.innerHeight]").await;
        let (inner_w, inner_h) = (inner[0].as_u64().unwrap_or(0), inner[1].as_u64().unwrap_or(0));
        if (inner_w, inner_h) != (u64::from(width), u64::from(height)) && inner_w > 0 {
            let w = u64::from(width) * 2 - inner_w;
            let h = u64::from(height) * 2 - inner_h;
            self.client
                .set_window_size(
                    u32::try_from(w).unwrap_or(width),
                    u32::try_from(h).unwrap_or(height),
                )
                .await
                .expect("window resized");
        }
    }

    /// Runs JavaScript in the page and returns its result.
    pub async fn eval(&self, script: &str) -> Value {
        self.client.execute(script, vec![]).await.expect("script runs")
    }

    /// Fails the test saying what it waited for and what the page showed instead.
    async fn gave_up<T>(&self, what: &str) -> T {
        let shown = self
            .eval("return location.hash + '\\n' + document.body.innerText.slice(0, 3000)")
            .await;
        panic!(
            "gave up after {:?} waiting for {what}; the page showed:\n{}",
            wait::DEADLINE,
            shown.as_str().unwrap_or_default()
        )
    }

    /// The first element matching `css` that is displayed, once there is one.
    pub async fn wait_for(&self, css: &str) -> Element {
        let found = wait::within(|| async {
            for element in self.client.find_all(Locator::Css(css)).await.ok()? {
                if element.is_displayed().await.unwrap_or(false) {
                    return Some(element);
                }
            }
            None
        })
        .await;
        match found {
            Some(element) => element,
            None => self.gave_up(&format!("{css} to be shown")).await,
        }
    }

    /// The first element matching `css` whose text contains `text`, once there is one.
    pub async fn wait_for_text(&self, css: &str, text: &str) -> Element {
        let found = wait::within(|| async {
            for element in self.client.find_all(Locator::Css(css)).await.ok()? {
                if element.text().await.is_ok_and(|shown| shown.contains(text)) {
                    return Some(element);
                }
            }
            None
        })
        .await;
        match found {
            Some(element) => element,
            None => self.gave_up(&format!("{css} to show {text:?}")).await,
        }
    }

    /// Waits until no displayed element matches `css` with a text containing `text`.
    pub async fn wait_gone(&self, css: &str, text: &str) {
        let gone = wait::within(|| async {
            for element in self.client.find_all(Locator::Css(css)).await.ok()? {
                let shown = element.is_displayed().await.unwrap_or(false);
                if shown && element.text().await.is_ok_and(|t| t.contains(text)) {
                    return None;
                }
            }
            Some(())
        })
        .await;
        if gone.is_none() {
            self.gave_up(&format!("{css} to stop showing {text:?}")).await
        }
    }

    /// Waits until the JavaScript expression `condition` is truthy in the page.
    pub async fn wait_until(&self, what: &str, condition: &str) {
        let script = format!("return Boolean({condition})");
        let held = wait::within(|| async {
            let value = self.client.execute(&script, vec![]).await.ok()?;
            value.as_bool().filter(|ok| *ok).map(|_| ())
        })
        .await;
        if held.is_none() {
            self.gave_up(what).await
        }
    }

    /// Replaces the text of the field matching `css`.
    pub async fn fill(&self, css: &str, text: &str) {
        let field = self.wait_for(css).await;
        field.clear().await.expect("field cleared");
        field.send_keys(text).await.expect("typed");
    }

    pub async fn click(&self, css: &str) {
        self.wait_for(css).await.click().await.expect("clicked");
    }

    /// Clicks the first displayed button or link matching `css` that shows `text`.
    pub async fn click_text(&self, css: &str, text: &str) {
        self.wait_for_text(css, text).await.click().await.expect("clicked");
    }

    /// Logs in through the form, submitting with Enter, and waits for the app.
    pub async fn log_in(&self, user: &str, password: &str) {
        self.open("/").await;
        self.fill("input[name=username]", user).await;
        self.fill("input[name=password]", &format!("{password}\u{E007}")).await;
        self.wait_for("nav.mainnav").await;
    }

    /// Saves a screenshot as `target/ui-screenshots/NAME.png` and returns its path.
    pub async fn screenshot(&self, name: &str) -> PathBuf {
        let png = self.client.screenshot().await.expect("a screenshot");
        let dir = target_dir().join("ui-screenshots");
        std::fs::create_dir_all(&dir).expect("screenshot directory");
        let path = dir.join(format!("{name}.png"));
        std::fs::write(&path, png).expect("screenshot written");
        path
    }

    /// Saves a screenshot of the whole page at the current width: the viewport is stretched
    /// to the page's height for the shot, then put back.
    pub async fn screenshot_full_page(&self, name: &str) -> PathBuf {
        let size = self.eval("return [window.innerWidth, window.innerHeight, document.documentElement.scrollHeight]").await;
        let dimension = |i: usize| u32::try_from(size[i].as_u64().unwrap_or(0)).unwrap_or(0);
        let (width, height, page_height) = (dimension(0), dimension(1), dimension(2));
        self.set_viewport((width, page_height.clamp(height, 6000))).await;
        self.eval("window.scrollTo(0, 0); return null").await;
        let path = self.screenshot(name).await;
        self.set_viewport((width, height)).await;
        path
    }

    /// The serious and critical accessibility violations axe-core finds in the page as it is
    /// now, one line each: the rule, what it asks for, and the elements that break it.
    pub async fn accessibility_problems(&self) -> Vec<String> {
        let axe = target_dir().join("axe-core/node_modules/axe-core/axe.min.js");
        let source = std::fs::read_to_string(&axe).unwrap_or_else(|e| {
            panic!(
                "{} is missing ({e}): run tests/axe-core/install, as tests/run does",
                axe.display()
            )
        });
        let script = format!(
            "const done = arguments[arguments.length - 1];\n{source}\n\
             axe.run(document, {{ resultTypes: ['violations'] }}).then((result) => done(\
               result.violations.filter((v) => v.impact === 'serious' || v.impact === 'critical')\
                 .map((v) => `${{v.impact}} ${{v.id}}: ${{v.help}} — ${{v.nodes.map((n) => n.target.join(' ')).join(', ')}}`)),\
               (error) => done([`axe-core failed: ${{error}}`]));"
        );
        let found = self.client.execute_async(&script, vec![]).await.expect("axe-core runs");
        found
            .as_array()
            .map(|lines| lines.iter().filter_map(|l| l.as_str().map(str::to_owned)).collect())
            .unwrap_or_default()
    }

    /// Whether the page fits its viewport without scrolling sideways.
    pub async fn fits_width(&self) -> bool {
        self.eval("return document.documentElement.scrollWidth <= window.innerWidth")
            .await
            .as_bool()
            .unwrap_or(false)
    }

    /// Ends the browser.
    pub async fn close(self) {
        let _ = self.client.close().await;
    }
}
