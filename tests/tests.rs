//! Integration tests, one binary (ripgrep's layout): each module below tests
//! one command or stage end to end through the `rocking` binary or the
//! library's public API.
//!
//! - `answers`: answers that once contradicted each other or physics, each
//!   named after its fault (hazard files, exports, records, periods,
//!   messages).
//! - `certify`: nonlinear capacities certified against DP5's tolerance (the
//!   hard cases against a tight search, a chaotic case flagged), the exact
//!   stepper's verdicts under a one-ulp change of the record.
//! - `cli`: `simulate` and `capacity` through the binary: JSON, history
//!   files, the definitions of η_c, bad input.
//! - `damage`: the damage stage's state capacities against the runs, its
//!   fits against the fractiles by hand and the likelihood's maximum; the
//!   states of `fragility` and `risk` from a study; refusals and staleness.
//! - `docs`: the generated references (docs/cli.md, docs/tables.md) equal
//!   what the code generates; every table and stage listed wherever they
//!   are; the README's and the guide's commands print what they show.
//! - `engines`: `rocking export` read by OpenQuake (classical_damage against
//!   `rocking risk` and its own formula) and pelicun (damage shares against
//!   the stated lognormals) (ROCKING_ENGINES=venv; CI makes one).
//! - `events`: `risk --gmf` against OpenQuake's event-based damage on its
//!   fields and the same run's hazard curves (`ROCKING_ENGINES`), the count
//!   distribution against a Monte Carlo by hand, bad fields refused.
//! - `example`: `[example]`, the report's Fig. 5 block run off the grid:
//!   capacities against direct calls, fractiles by hand, the same block on
//!   the grid against the sweep, reruns, refusals.
//! - `faults`: the faults a hostile user finds (absurd sizes, corrupt parts, mixed
//!   shards, misleading hints, thread counts, escaped file contents,
//!   manifest lines, copied folders, hand-edited figures, typed reasons).
//! - `floor`: a block on a building's floor (the floor motion is what runs,
//!   PFA/PGA, the ground's PGA) and the sliding check in every command.
//! - `html`: `report.html` loaded in headless Chromium, every figure drawn
//!   (ROCKING_CHROMIUM=1; CI sets it).
//! - `ims`: `rocking ims` (PGV against FEMA P695's table, the JSON, bad
//!   input) and the ims stage's dispersions against the capacities by hand.
//! - `ingest`: the records table from the bundled FEMA P695 files, checked
//!   against the manifest and the files; bad input and atomic output.
//! - `notebook`: the contents notebook executed by nbclient (`ROCKING_ENGINES`).
//! - `opensees`: an OpenSeesPy building's floor motions → the tool's PFV
//!   fragilities → pelicun, beside FEMA P-58's bookcases and direct runs
//!   (`ROCKING_ENGINES`, with openseespy).
//! - `pairs`: record pairs: RotD50/RotD100 against Newmark-integrated
//!   responses rotated every 1°, capacities at the axes and mirrored angles.
//! - `physics`: the solvers against closed forms, conservation laws,
//!   symmetry and the hard cases (`ida::HARD_CASES`).
//! - `tree`: a logic tree over ε and the model against plain runs at each
//!   branch (mean, quantiles by hand, one branch to the bit), the rate's
//!   bootstrap band against a bootstrap by hand, a study's tree stage
//!   against direct capacities, pelicun's mean curve against the mixture.
//! - `taylor`: the Taylor stepper of the nonlinear equation against the
//!   energy of free rocking, DP5 at 1e-13, the linearised closed form as
//!   α → 0, and the hard cases; choosing it and refusals.
//! - `pulse`: pulses and `escape`: the walls against Eqs. 3, 5 and 6, the
//!   full-cycle modes against a piecewise closed form, the pulse-map
//!   pipeline, refusals.
//! - `python`: the Python package's pytest suite against the command line's
//!   JSON, and the README's two Python lines (ROCKING_PYPKG; CI sets it).
//! - `quick`: the quick study unchanged from before the redesign, and the
//!   analyst queries of outputs/README.md checked against its tables
//!   (ROCKING_SLOW=1).
//! - `reduce`: reduce, fit and fragility: definitions, Lilliefors by Monte
//!   Carlo, the regression on synthetic data, reruns; the paper's grid
//!   against Eq. 10 when ROCKING_SLOW=1 (CI sets it).
//! - `risk`: the annual rate of overturning against Cornell's closed form,
//!   a quadrature of its own, and the records' capacities (`--direct`); the
//!   inventory table; every refusal of a hazard file.
//! - `run`: the cached pipeline run: reruns for the right reasons, the lock,
//!   and a snapshot of a mini study (tests/snapshots, `ROCKING_BLESS=1`).
//! - `slurm`: `rocking submit` on a single-node Slurm this test starts
//!   (ROCKING_SLURM=1, as root; CI sets it), against a local run.
//! - `sweep`: pipelines load; bad ones fail first; capacities against direct
//!   calls; byte-identical at 1 and 2 threads; shards; resume after a crash.
//! - `tables`: Parquet round trips, atomic writes, foreign files refused.
//! - `util`: helpers (running the binary, an independent AT2 reader).

mod answers;
mod certify;
mod cli;
mod damage;
mod docs;
mod engines;
mod events;
mod example;
mod faults;
mod floor;
mod html;
mod ims;
mod ingest;
mod notebook;
mod opensees;
mod pairs;
mod physics;
mod pulse;
mod python;
mod quick;
mod reduce;
mod risk;
mod run;
mod slide;
mod slurm;
mod sweep;
mod tables;
mod taylor;
mod tree;
mod util;
