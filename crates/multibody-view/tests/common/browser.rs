//! Headless Chromium: opens a page from disk and takes a screenshot, with
//! the browser's log (console messages included) for error checks.

use super::pixels::Image;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

/// The browser the tests drive: `/usr/bin/chromium` (Debian's package), or
/// `$MULTIBODY_CHROMIUM`.
pub fn chromium() -> PathBuf {
    let path = std::env::var_os("MULTIBODY_CHROMIUM").map(PathBuf::from).unwrap_or_else(|| "/usr/bin/chromium".into());
    assert!(
        path.exists(),
        "the view tests need headless Chromium at {}, which is missing: run scripts/install-test-deps.sh \
         (it installs Debian's chromium), or point MULTIBODY_CHROMIUM at a Chromium binary",
        path.display()
    );
    path
}

/// A screenshot and what the browser logged while taking it.
pub struct Shot {
    pub image: Image,
    pub log: String,
}

impl Shot {
    /// Lines of the log that the page logged (console messages).
    pub fn console(&self) -> Vec<&str> {
        self.log.lines().filter(|l| l.contains(":CONSOLE")).collect()
    }

    /// Fails unless the page rendered and reported no error: no error of
    /// its own (window errors, WebGL missing, shader failures), no uncaught
    /// exception and no WebGL error in the console.
    pub fn assert_clean(&self) {
        assert!(
            self.console().iter().any(|l| l.contains("multibody-view: rendered")),
            "the page did not finish rendering; browser log:\n{}",
            self.log
        );
        self.assert_no_errors();
    }

    /// Fails if the page reported an error (a page without a 3-D view, of
    /// a model without shapes, renders nothing and says so by not logging).
    pub fn assert_no_errors(&self) {
        let console = self.console();
        let bad: Vec<&&str> = console
            .iter()
            .filter(|l| {
                l.contains("multibody-view error")
                    || l.contains("Uncaught")
                    || l.contains("WebGL: INVALID")
                    || l.contains("GL_INVALID")
                    || l.contains("TypeError")
                    || l.contains("ReferenceError")
            })
            .collect();
        assert!(bad.is_empty(), "the page logged errors:\n{bad:#?}");
    }
}

/// Opens `page` with the query string `query` in a window of `size` and
/// returns the screenshot; `name` names the scratch folder.
pub fn screenshot(page: &Path, query: &str, size: (u32, u32), name: &str) -> Shot {
    let browser = chromium();
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("browser").join(name);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let shot = dir.join("shot.png");
    let profile = dir.join("profile");
    let log = dir.join("browser.log");
    let page = page.canonicalize().unwrap();
    let url = format!("file://{}?{query}", page.display());
    let mut child = Command::new(browser)
        .args([
            "--headless",
            "--no-sandbox",
            "--disable-gpu",
            // WebGL without a GPU: ANGLE on SwiftShader, Chromium's software
            // renderer, which recent versions only enable on request.
            "--use-angle=swiftshader",
            "--enable-unsafe-swiftshader",
            "--disable-quic",
            "--no-first-run",
            "--disable-background-networking",
            "--disable-component-update",
            "--disable-sync",
            "--disable-extensions",
            "--hide-scrollbars",
            "--force-device-scale-factor=1",
            "--enable-logging=stderr",
            "--v=0",
        ])
        .arg(format!("--user-data-dir={}", profile.display()))
        .arg(format!("--screenshot={}", shot.display()))
        .arg(format!("--window-size={},{}", size.0, size.1))
        .arg(&url)
        .stdin(Stdio::null())
        .stdout(std::fs::File::create(dir.join("browser.out")).unwrap())
        .stderr(std::fs::File::create(&log).unwrap())
        .spawn()
        .expect("chromium starts");
    let started = Instant::now();
    let status = loop {
        if let Some(status) = child.try_wait().unwrap() {
            break status;
        }
        if started.elapsed() > Duration::from_secs(90) {
            let _ = child.kill();
            let _ = child.wait();
            panic!("chromium took more than 90 s on {url}; log in {}", log.display());
        }
        std::thread::sleep(Duration::from_millis(50));
    };
    let log_text = std::fs::read_to_string(&log).unwrap_or_default();
    assert!(status.success(), "chromium failed ({status}) on {url}:\n{log_text}");
    let image = Image::read(&shot);
    let _ = std::fs::remove_dir_all(&profile);
    Shot { image, log: log_text }
}
