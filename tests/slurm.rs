//! `rocking submit` on a real Slurm (`ROCKING_SLURM=1`, which
//! `.ci/run` sets after installing Debian's `slurm-wlm` and `munge`).
//!
//! The test stands up a single-node cluster on this machine: munged,
//! slurmctld and slurmd in the foreground as its own children, with a
//! minimal slurm.conf for this host (`ProctrackType=proctrack/linuxproc`,
//! `TaskPlugin=task/none`, no accounting) and every file in a temporary
//! folder, and stops them by their process ids when it ends. Then
//! `rocking submit pipelines/quick.toml --shards 3 --wait` must produce
//! every table a local `rocking run` does, value for value; and a sweep
//! whose tasks crash must make `--wait` fail naming the task and its log.

use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

use rocking::stages::sweep::{read_capacities, read_ida, FAULT_ENV};

use crate::util::{dump_columns, root, stderr, tempdir, TempDir};

/// A program from PATH or the system folders daemons live in.
fn program(name: &str) -> PathBuf {
    let path = std::env::var_os("PATH").unwrap_or_default();
    std::env::split_paths(&path)
        .chain(["/usr/sbin", "/sbin", "/usr/bin"].map(PathBuf::from))
        .map(|d| d.join(name))
        .find(|p| p.is_file())
        .unwrap_or_else(|| {
            panic!(
                "ROCKING_SLURM is set but `{name}` is not installed: the Slurm test needs \
                 Debian's slurm-wlm and munge (`apt-get install slurm-wlm munge`, as .ci/run does)"
            )
        })
}

fn free_port() -> u16 {
    std::net::TcpListener::bind("127.0.0.1:0")
        .unwrap()
        .local_addr()
        .unwrap()
        .port()
}

/// A single-node Slurm whose daemons are this test's children.
struct Cluster {
    dir: TempDir,
    conf: PathBuf,
    daemons: Vec<(String, Child)>,
}

impl Drop for Cluster {
    /// Stops the daemons it started, by their process ids.
    fn drop(&mut self) {
        for (_, child) in self.daemons.iter_mut().rev() {
            let _ = child.kill();
            let _ = child.wait();
        }
    }
}

impl Cluster {
    fn path(&self, name: &str) -> PathBuf {
        self.dir.path().join(name)
    }

    fn spawn(&mut self, name: &str, cmd: &mut Command) {
        let log = std::fs::File::create(self.path(&format!("{name}.out"))).unwrap();
        let child = cmd
            .stdout(Stdio::from(log.try_clone().unwrap()))
            .stderr(Stdio::from(log))
            .spawn()
            .unwrap_or_else(|e| panic!("cannot start {name}: {e}"));
        self.daemons.push((name.to_string(), child));
    }

    /// The daemons' own words, for a failure message.
    fn logs(&self) -> String {
        [
            "munged.out",
            "slurmctld.out",
            "slurmd.out",
            "slurmctld.log",
            "slurmd.log",
        ]
        .iter()
        .map(|f| {
            let text = std::fs::read_to_string(self.path(f)).unwrap_or_default();
            let tail: Vec<&str> = text.lines().rev().take(15).collect();
            format!(
                "--- {f}\n{}",
                tail.into_iter().rev().collect::<Vec<_>>().join("\n")
            )
        })
        .collect::<Vec<_>>()
        .join("\n")
    }

    fn start() -> Cluster {
        use std::os::unix::fs::PermissionsExt;
        // slurmd runs jobs as their users, so it must run as root.
        let uid = std::fs::read_to_string("/proc/self/status")
            .unwrap()
            .lines()
            .find_map(|l| l.strip_prefix("Uid:"))
            .and_then(|l| l.split_whitespace().next().map(str::to_string))
            .unwrap();
        assert_eq!(
            uid, "0",
            "the Slurm test starts slurmd, which must run as root"
        );
        let dir = tempdir();
        let mut c = Cluster {
            conf: dir.path().join("slurm.conf"),
            dir,
            daemons: Vec::new(),
        };
        for sub in ["munge", "state", "spool"] {
            std::fs::create_dir_all(c.path(sub)).unwrap();
        }
        std::fs::set_permissions(c.dir.path(), std::fs::Permissions::from_mode(0o755)).unwrap();
        let key = c.path("munge/munge.key");
        let mut random = vec![0u8; 1024];
        use std::io::Read;
        std::fs::File::open("/dev/urandom")
            .unwrap()
            .read_exact(&mut random)
            .unwrap();
        std::fs::write(&key, &random).unwrap();
        std::fs::set_permissions(&key, std::fs::Permissions::from_mode(0o400)).unwrap();
        let socket = c.path("munge/munge.socket.2");
        let munge = |f: &str| c.path(&format!("munge/{f}"));
        let mut munged = Command::new(program("munged"));
        munged.args([
            "--foreground",
            "--force",
            &format!("--socket={}", socket.display()),
            &format!("--key-file={}", key.display()),
            &format!("--log-file={}", munge("munged.log").display()),
            &format!("--pid-file={}", munge("munged.pid").display()),
            &format!("--seed-file={}", munge("munged.seed").display()),
        ]);
        c.spawn("munged", &mut munged);
        c.wait_for("munged's socket", || socket.exists());

        let host = std::fs::read_to_string("/proc/sys/kernel/hostname")
            .unwrap()
            .trim()
            .to_string();
        let cpus = std::thread::available_parallelism().map_or(1, |n| n.get());
        let d = c.dir.path().display().to_string();
        let conf = format!(
            "ClusterName=rockingtest\n\
             SlurmctldHost={host}(127.0.0.1)\n\
             SlurmUser=root\nSlurmdUser=root\n\
             AuthType=auth/munge\nCredType=cred/munge\n\
             AuthInfo=socket={socket}\n\
             StateSaveLocation={d}/state\nSlurmdSpoolDir={d}/spool\n\
             SlurmctldPidFile={d}/slurmctld.pid\nSlurmdPidFile={d}/slurmd.pid\n\
             SlurmctldLogFile={d}/slurmctld.log\nSlurmdLogFile={d}/slurmd.log\n\
             SlurmctldPort={}\nSlurmdPort={}\n\
             ProctrackType=proctrack/linuxproc\nTaskPlugin=task/none\n\
             SchedulerType=sched/backfill\nSelectType=select/cons_tres\n\
             SelectTypeParameters=CR_Core\nReturnToService=2\nMpiDefault=none\n\
             JobAcctGatherType=jobacct_gather/none\n\
             AccountingStorageType=accounting_storage/none\nJobCompType=jobcomp/none\n\
             MinJobAge=3600\n\
             NodeName={host} NodeAddr=127.0.0.1 CPUs={cpus} State=UNKNOWN\n\
             PartitionName=debug Nodes={host} Default=YES MaxTime=INFINITE State=UP\n",
            free_port(),
            free_port(),
            socket = socket.display(),
        );
        std::fs::write(&c.conf, conf).unwrap();
        let conf_path = c.conf.clone();
        c.spawn(
            "slurmctld",
            Command::new(program("slurmctld"))
                .arg("-D")
                .arg("-f")
                .arg(&conf_path),
        );
        c.spawn(
            "slurmd",
            Command::new(program("slurmd"))
                .arg("-D")
                .arg("-f")
                .arg(&conf_path)
                .args(["-N", &host]),
        );
        let sinfo = program("sinfo");
        c.wait_for("the node to be idle", || {
            Command::new(&sinfo)
                .args(["-h", "-o", "%t"])
                .env("SLURM_CONF", &conf_path)
                .output()
                .is_ok_and(|o| String::from_utf8_lossy(&o.stdout).trim() == "idle")
        });
        c
    }

    fn wait_for(&self, what: &str, ready: impl Fn() -> bool) {
        let start = Instant::now();
        while !ready() {
            assert!(
                start.elapsed() < Duration::from_secs(60),
                "waited 60 s for {what}:\n{}",
                self.logs()
            );
            std::thread::sleep(Duration::from_millis(200));
        }
    }

    /// `rocking ARGS` from the repository root, as a Slurm user would type
    /// it (`SLURM_CONF` naming this cluster), stopped after `limit`.
    fn rocking(
        &self,
        args: &[&str],
        env: &[(&str, &str)],
        limit: Duration,
    ) -> std::process::Output {
        let mut cmd = Command::new(env!("CARGO_BIN_EXE_rocking"));
        cmd.args(args)
            .current_dir(root())
            .env("SLURM_CONF", &self.conf)
            .stdout(Stdio::piped())
            .stderr(Stdio::piped());
        for (k, v) in env {
            cmd.env(k, v);
        }
        let mut child = cmd.spawn().unwrap();
        let start = Instant::now();
        while child.try_wait().unwrap().is_none() {
            if start.elapsed() > limit {
                let _ = child.kill();
                panic!("rocking {args:?} ran over {limit:?}:\n{}", self.logs());
            }
            std::thread::sleep(Duration::from_millis(100));
        }
        child.wait_with_output().unwrap()
    }
}

/// Every table of the local study against the submitted one, value for
/// value; the sweep's (sharded there) through the readers that merge shards.
fn assert_same_tables(local: &Path, submitted: &Path) {
    assert_eq!(
        read_capacities(submitted).unwrap(),
        read_capacities(local).unwrap()
    );
    assert_eq!(read_ida(submitted).unwrap(), read_ida(local).unwrap());
    let mut compared = 0;
    for entry in std::fs::read_dir(local).unwrap() {
        let path = entry.unwrap().path();
        let name = path.file_name().unwrap().to_string_lossy().into_owned();
        if !name.ends_with(".parquet")
            || name == "capacities.parquet"
            || name == "ida_points.parquet"
        {
            continue;
        }
        let other = submitted.join(&name);
        assert!(other.exists(), "{name} missing from the submitted study");
        assert_eq!(
            dump_columns(&other, true, None),
            dump_columns(&path, true, None),
            "{name} differs"
        );
        compared += 1;
    }
    // The quick study writes 19 tables beside the sweep's two (its
    // pipeline's stages: convergence, ims, reduce, fit, damage, figures'
    // data); a count that guards the loop against comparing nothing.
    assert_eq!(compared, 19, "every table beyond the sweep's was compared");
    // And the submitted study holds no table the local one lacks.
    for entry in std::fs::read_dir(submitted).unwrap() {
        let name = entry.unwrap().file_name().to_string_lossy().into_owned();
        if name.ends_with(".parquet") && !name.contains(".shard-") {
            assert!(
                local.join(&name).exists(),
                "{name} only in the submitted study"
            );
        }
    }
    assert!(submitted.join("report.md").exists() && submitted.join("report.html").exists());
}

#[test]
fn submit_runs_the_quick_study_on_a_real_slurm() {
    if std::env::var("ROCKING_SLURM").is_err() {
        eprintln!("skipped: set ROCKING_SLURM=1 (as root, with slurm-wlm and munge) to run");
        return;
    }
    let cluster = Cluster::start();
    let out = tempdir();
    let submitted = out.path().join("slurm");
    let limit = Duration::from_secs(600);
    // The quick study in 3 array tasks, followed to the end.
    let submit = |outputs: &Path, env: &[(&str, &str)]| {
        let outputs = outputs.to_str().unwrap();
        let args = [
            "submit",
            "pipelines/quick.toml",
            "--shards",
            "3",
            "--wait",
            "--poll",
            "0.5",
        ];
        cluster.rocking(&[&args[..], &["--outputs", outputs]].concat(), env, limit)
    };
    let run = submit(&submitted, &[]);
    assert!(run.status.success(), "{}\n{}", stderr(&run), cluster.logs());
    let text = String::from_utf8_lossy(&run.stdout);
    assert!(
        text.contains("(3 array tasks)") && text.contains("done: report"),
        "{text}"
    );
    let study = submitted.join("quick");
    for k in 1..=3 {
        assert!(study
            .join(format!("ida_points.shard-{k}-of-3.parquet"))
            .exists());
    }
    // The scripts are kept, and the array is what they say.
    let script = std::fs::read_to_string(study.join("slurm/sweep.sbatch")).unwrap();
    assert!(script.contains("#SBATCH --array=1-3"), "{script}");

    let local = out.path().join("local");
    let here = cluster.rocking(
        &[
            "run",
            "pipelines/quick.toml",
            "--outputs",
            local.to_str().unwrap(),
        ],
        &[],
        limit,
    );
    assert!(here.status.success(), "{}", stderr(&here));
    assert_same_tables(&local.join("quick"), &study);

    // A floor study (`[floor]`) in 2 array tasks: the capacities a local run
    // finds, each record's PFA/PGA and sliding flag included.
    // Its outputs in a folder with a space, a quote, a `#` and letters
    // beyond ASCII: the scripts' directives carry them (sbatch refused an
    // unquoted space as an "Invalid directive").
    let floor_out = out.path().join("floor it's #1 ünï");
    let floor_args = [
        "submit",
        "pipelines/floor.toml",
        "--shards",
        "2",
        "--wait",
        "--poll",
        "0.5",
        "--outputs",
        floor_out.to_str().unwrap(),
        // A user's option whose value has a space, a quote and a `#`.
        "--sbatch=--comment=a study's run #1",
    ];
    let run = cluster.rocking(&floor_args, &[], limit);
    assert!(run.status.success(), "{}\n{}", stderr(&run), cluster.logs());
    let here = cluster.rocking(
        &[
            "run",
            "pipelines/floor.toml",
            "--outputs",
            local.to_str().unwrap(),
        ],
        &[],
        limit,
    );
    assert!(here.status.success(), "{}", stderr(&here));
    let caps = |dir: &Path| rocking::stages::sweep::read_capacities(&dir.join("floor")).unwrap();
    let (submitted_caps, local_caps) = (caps(&floor_out), caps(&local));
    assert_eq!(submitted_caps.len(), 44 * 4);
    assert_eq!(submitted_caps, local_caps);
    assert!(submitted_caps.iter().all(|c| c.pfa_over_pga.is_some()));
    assert!(floor_out.join("floor/figures/floor_capacity.svg").exists());

    // Tasks that crash (the fault-injection hook aborts each task once its
    // first chunk is complete): --wait fails, naming a task and its log, and the later
    // stages never run.
    // In a folder with a space: the log named is the task's whole path
    // (`scontrol -o` cuts a value at its spaces).
    let failing = out.path().join("fail ing");
    let bad = submit(&failing, &[(FAULT_ENV, "1")]);
    assert!(!bad.status.success());
    let e = stderr(&bad);
    assert!(
        e.contains("sweep task") && e.contains("FAILED") && e.contains("its log: /"),
        "{e}"
    );
    let log = e
        .split("its log: ")
        .nth(1)
        .and_then(|s| s.split(". The later").next())
        .unwrap();
    assert!(Path::new(log).exists(), "the log named exists: {log}");
    assert!(
        !failing.join("quick/report.md").exists(),
        "the later stages did not run"
    );
}

/// `rocking submit pipelines/quick.toml --shards 2` into `outputs`, with
/// only `path` on PATH.
fn submit_quick(outputs: &Path, path: &Path) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_rocking"))
        .args([
            "submit",
            "pipelines/quick.toml",
            "--shards",
            "2",
            "--outputs",
        ])
        .arg(outputs)
        .current_dir(root())
        .env("PATH", path)
        .output()
        .unwrap()
}

#[test]
fn submit_without_sbatch_says_so() {
    let dir = tempdir();
    let out = submit_quick(dir.path(), dir.path());
    assert!(!out.status.success());
    let e = stderr(&out);
    assert!(e.contains("needs Slurm's `sbatch` on PATH"), "{e}");
    // Refused before anything was written.
    assert!(!dir.path().join("quick").exists(), "{e}");
}

/// `--shards 0` was refused as the shard `1/0`; it is refused as a count.
#[test]
fn zero_shards_are_refused_as_a_count() {
    let out = crate::util::rocking(
        &root(),
        &["submit", "pipelines/quick.toml", "--shards", "0"],
    );
    assert!(!out.status.success());
    let e = stderr(&out);
    assert!(
        e.contains("--shards") && e.contains("1 shard or more") && !e.contains("1/0"),
        "{e}"
    );
}

/// An `sbatch` that refuses the job leaves no scripts behind (they once
/// stayed in `slurm/` beside nothing submitted).
#[test]
fn a_refused_submission_leaves_no_scripts() {
    let dir = tempdir();
    let bin = dir.path().join("bin");
    std::fs::create_dir(&bin).unwrap();
    let sbatch = bin.join("sbatch");
    std::fs::write(
        &sbatch,
        "#!/bin/sh\necho 'sbatch: error: invalid partition' >&2\nexit 1\n",
    )
    .unwrap();
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        std::fs::set_permissions(&sbatch, std::fs::Permissions::from_mode(0o755)).unwrap();
    }
    let out = submit_quick(&dir.path().join("out"), &bin);
    assert!(!out.status.success());
    let e = stderr(&out);
    assert!(e.contains("invalid partition"), "{e}");
    assert!(!dir.path().join("out/quick/slurm").exists(), "{e}");
}

/// An array of more tasks than the sweep has chunks was submitted, and
/// every task refused its shard (`--shard 17/40`: at most 17 shards have
/// work), so the later stages never ran, found out on the cluster. It is
/// refused before `sbatch` is called: the quick study's 12 blocks × 44
/// records are 528 cases, 17 chunks of 32; 17 tasks are submitted.
#[test]
fn more_shards_than_chunks_are_refused_before_submitting() {
    let dir = tempdir();
    let bin = dir.path().join("bin");
    std::fs::create_dir(&bin).unwrap();
    let called = dir.path().join("called");
    let sbatch = bin.join("sbatch");
    std::fs::write(
        &sbatch,
        format!(
            "#!/bin/sh\necho \"$@\" >> {}\necho 4242\n",
            called.display()
        ),
    )
    .unwrap();
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        std::fs::set_permissions(&sbatch, std::fs::Permissions::from_mode(0o755)).unwrap();
    }
    let submit = |shards: &str| {
        Command::new(env!("CARGO_BIN_EXE_rocking"))
            .args([
                "submit",
                "pipelines/quick.toml",
                "--shards",
                shards,
                "--outputs",
            ])
            .arg(dir.path().join("out"))
            .current_dir(root())
            .env("PATH", &bin)
            .output()
            .unwrap()
    };
    let chunks = (12usize * 44).div_ceil(32);
    let out = submit(&(chunks + 1).to_string());
    assert!(!out.status.success());
    let e = stderr(&out);
    assert!(
        e.contains(&format!("at most {chunks} array tasks have work")),
        "{e}"
    );
    assert!(!called.exists(), "sbatch was called: {e}");
    let out = submit(&chunks.to_string());
    assert!(out.status.success(), "{}", stderr(&out));
    let calls = std::fs::read_to_string(&called).unwrap();
    assert_eq!(calls.lines().count(), 2, "{calls}");
}

/// Writes an executable shell script `name` into `bin`.
fn fake(bin: &Path, name: &str, body: &str) {
    let path = bin.join(name);
    std::fs::write(&path, format!("#!/bin/sh\n{body}")).unwrap();
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        std::fs::set_permissions(&path, std::fs::Permissions::from_mode(0o755)).unwrap();
    }
}

/// `--wait` asked Slurm about the sweep's array at every poll, also after
/// its tasks were seen done; Slurm forgets a finished job after MinJobAge
/// (300 s by default), so a study whose later stages ran longer failed
/// ("Slurm no longer knows job 1001") although it succeeded. A fake
/// Slurm: the array (1001) completed at the first poll and unknown after,
/// the later job (1002) running for two polls, then completed.
#[test]
fn wait_follows_the_later_job_after_slurm_forgets_the_finished_array() {
    let done =
        "1001:1) echo 'JobId=1003 ArrayJobId=1001 ArrayTaskId=1 JobState=COMPLETED ExitCode=0:0'\n\
                echo 'JobId=1004 ArrayJobId=1001 ArrayTaskId=2 JobState=COMPLETED ExitCode=0:0' ;;";
    let (dir, out) = wait_on_fake_slurm(done, "1002:1|1002:2");
    assert!(out.status.success(), "{}", stderr(&out));
    let said = format!("{}{}", String::from_utf8_lossy(&out.stdout), stderr(&out));
    assert!(
        said.contains("later stages (job 1002) completed") && said.contains("done: report"),
        "{said}"
    );
    // The array was asked about once: at the poll that saw it done.
    let asked = std::fs::read_to_string(dir.path().join("asked-1001")).unwrap();
    assert_eq!(asked.lines().count(), 1);
    assert!(
        !dir.path().join("scancel").exists(),
        "nothing was cancelled"
    );
    // Forgotten before its last task was seen done, while the later job
    // (which starts only after every task succeeded) runs: done, not purged.
    let half =
        "1001:1) echo 'JobId=1003 ArrayJobId=1001 ArrayTaskId=1 JobState=COMPLETED ExitCode=0:0'\n\
                echo 'JobId=1004 ArrayJobId=1001 ArrayTaskId=2 JobState=RUNNING ExitCode=0:0' ;;";
    let (_dir, out) = wait_on_fake_slurm(half, "1002:1|1002:2|1002:3");
    assert!(out.status.success(), "{}", stderr(&out));
    // Forgotten while the later job still waits: that is not known to have
    // succeeded, and is said.
    let (_dir, out) = wait_on_fake_slurm(half, "1002:0");
    assert!(!out.status.success());
    assert!(
        stderr(&out).contains("Slurm no longer knows job 1001"),
        "{}",
        stderr(&out)
    );
}

/// `rocking submit pipelines/quick.toml --shards 2 --wait` against a fake
/// Slurm: `array` is the scontrol case of the array's first answer
/// (`1001:1) …;;`; asked again, it is unknown), `running` the polls of the
/// later job (1002) that find it running, after which it is completed
/// (`1002:0` never running: pending until then).
fn wait_on_fake_slurm(array: &str, running: &str) -> (TempDir, std::process::Output) {
    let dir = tempdir();
    let bin = dir.path().join("bin");
    std::fs::create_dir(&bin).unwrap();
    let d = dir.path().display();
    fake(
        &bin,
        "sbatch",
        &format!("echo x >> '{d}/sbatch'\nwc -l < '{d}/sbatch' | sed 's/ //g; s/^/100/'\n"),
    );
    fake(&bin, "scancel", &format!("echo \"$@\" >> '{d}/scancel'\n"));
    let later = match running {
        "1002:0" => "1002:*) echo 'JobId=1002 JobState=PENDING ExitCode=0:0' ;;".to_string(),
        r => format!(
            "{r}) echo 'JobId=1002 JobState=RUNNING ExitCode=0:0' ;;\n\
             1002:*) echo 'JobId=1002 JobState=COMPLETED ExitCode=0:0' ;;"
        ),
    };
    fake(
        &bin,
        "scontrol",
        &format!(
            "id=$4\necho x >> \"{d}/asked-$id\"\nn=$(wc -l < \"{d}/asked-$id\" | sed 's/ //g')\n\
             case \"$id:$n\" in\n{array}\n\
             1001:*) echo 'slurm_load_jobs error: Invalid job id specified' >&2; exit 1 ;;\n\
             {later}\n\
             esac\n"
        ),
    );
    let path = format!("{}:/usr/bin:/bin", bin.display());
    let out = Command::new(env!("CARGO_BIN_EXE_rocking"))
        .args(["submit", "pipelines/quick.toml", "--shards", "2", "--wait"])
        .args(["--poll", "0.05", "--outputs"])
        .arg(dir.path().join("out"))
        .current_dir(root())
        .env("PATH", &path)
        .output()
        .unwrap();
    (dir, out)
}
