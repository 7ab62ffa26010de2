//! Shows what a running study says: each stage as it starts or is skipped
//! (with why), notes, and progress as a bar with rate and ETA on a terminal,
//! plain log lines (every 10 s) otherwise. All on stderr.

use std::io::IsTerminal;
use std::sync::Mutex;
use std::time::Instant;

use rocking::stages::{Progress, Reporter, StageEvent};

pub struct Terminal {
    state: Mutex<State>,
}

struct State {
    tty: bool,
    started: Instant,
    last_log: Option<Instant>,
    drawn: bool,
}

impl Terminal {
    pub fn new() -> Self {
        Terminal {
            state: Mutex::new(State {
                tty: std::io::stderr().is_terminal(),
                started: Instant::now(),
                last_log: None,
                drawn: false,
            }),
        }
    }

    fn lock(&self) -> std::sync::MutexGuard<'_, State> {
        self.state.lock().unwrap_or_else(|e| e.into_inner())
    }
}

impl State {
    /// Ends a progress bar line before anything else is printed.
    fn clear_bar(&mut self) {
        if self.drawn {
            eprintln!();
            self.drawn = false;
        }
    }
}

impl Reporter for Terminal {
    fn stage(&self, stage: &'static str, event: &StageEvent) {
        let mut st = self.lock();
        st.clear_bar();
        match event {
            StageEvent::Running(reason) => {
                st.started = Instant::now();
                st.last_log = None;
                eprintln!("{stage:<12} running: {reason}");
            }
            StageEvent::Skipped(why) => eprintln!("{stage:<12} skipped: {why}"),
            StageEvent::Done { .. } => {}
        }
    }

    fn note(&self, stage: &'static str, text: &str) {
        let mut st = self.lock();
        st.clear_bar();
        eprintln!("{stage}: {text}");
    }

    fn progress(&self, p: &Progress) {
        let mut st = self.lock();
        let elapsed = st.started.elapsed().as_secs_f64();
        let computed = p.done.saturating_sub(p.resumed);
        let rate = computed as f64 / elapsed.max(1e-9);
        let eta = if computed > 0 {
            format!("{:.0} s", (p.total - p.done) as f64 / rate)
        } else {
            "?".into()
        };
        let runs_rate = p.runs as f64 / elapsed.max(1e-9);
        let (done, total) = (p.done, p.total);
        if st.tty {
            let width = 30u64;
            let filled = (done * width).checked_div(total).unwrap_or(width) as usize;
            eprint!(
                "\r{} [{}{}] {done}/{total}, {runs_rate:.0} runs/s, ETA {eta}   ",
                p.stage,
                "#".repeat(filled),
                " ".repeat(width as usize - filled)
            );
            st.drawn = true;
        } else if st
            .last_log
            .is_none_or(|t| t.elapsed().as_secs_f64() >= 10.0)
            || done == total
        {
            eprintln!(
                "{}: {done}/{total}, {} runs, {runs_rate:.0} runs/s, ETA {eta}",
                p.stage, p.runs
            );
            st.last_log = Some(Instant::now());
        }
    }
}

impl Drop for Terminal {
    fn drop(&mut self) {
        self.lock().clear_bar();
    }
}
