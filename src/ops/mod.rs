//! What the commands that are not stages do, as library calls the binary
//! wraps: load one record for the solvers ([`record`]), many capacities in one process ([`capacity`]), the fragility of a
//! real block ([`fragility`]) and of its damage states ([`damage`]) written for OpenQuake and pelicun ([`export`]), the annual rate of overturning at a site
//! ([`risk`]), and a study submitted to Slurm ([`submit`]). Input checks live here, not in the
//! argument parser, so tests and other front ends get them too.

pub mod capacity;
pub mod contents;
pub mod damage;
pub mod export;
pub mod fragility;
pub mod im_fragility;
pub mod pool;
pub mod record_ims;
pub mod reports;
pub mod risk;
pub mod submit;
pub mod tree;
