//! Every limit state's lognormals over a suite of records, in one IM: the
//! records' capacities (in η) stated in the IM, then fitted both ways.

use super::{fractile_method, max_likelihood, Lognormal, StateCapacity};
use crate::stats::FractileDef;

/// One state's capacities over the records, fitted.
#[derive(Debug, Clone, PartialEq)]
pub struct StateFit {
    /// Records that reach the state within their runs.
    pub reached: usize,
    /// Every record's capacity in the IM, ascending, +∞ for a record that
    /// never reaches the state: the records' curve is drawn through them.
    pub capacities: Vec<f64>,
    /// By the paper's fractiles (a record that never reaches it counts as +∞).
    pub fractile: Option<Lognormal>,
    /// By maximum likelihood, the others censored at their strongest run.
    pub mle: Option<Lognormal>,
}

/// The fits of each of `n_states` states from `caps[k][j]`, record k's
/// capacity for state j (in η), with `im_of(k, η)` record k's IM when
/// scaled to η. `None` when some record has no value of the IM (an SA
/// period it was not computed at).
pub fn fit_states(
    n_states: usize,
    caps: &[Vec<StateCapacity>],
    im_of: impl Fn(usize, f64) -> Option<f64>,
    def: FractileDef,
) -> Option<Vec<StateFit>> {
    (0..n_states)
        .map(|j| {
            let (mut reached, mut censored, mut all) = (Vec::new(), Vec::new(), Vec::new());
            for (k, record) in caps.iter().enumerate() {
                match record[j] {
                    StateCapacity::Reached(eta) => {
                        let v = im_of(k, eta)?;
                        reached.push(v);
                        all.push(v);
                    }
                    StateCapacity::NotReached(eta) => {
                        censored.push(im_of(k, eta)?);
                        all.push(f64::INFINITY);
                    }
                }
            }
            all.sort_by(f64::total_cmp);
            Some(StateFit {
                reached: reached.len(),
                fractile: fractile_method(&all, def),
                mle: max_likelihood(&reached, &censored),
                capacities: all,
            })
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Four records, one state reached by three: in PGA (η → α/η with
    /// α = 0.2) the fractile method takes the fourth as +∞, maximum
    /// likelihood censors it at its strongest run; a record without the
    /// IM gives no fit.
    #[test]
    fn states_fitted_in_the_im() {
        let caps = vec![
            vec![StateCapacity::Reached(0.5)],
            vec![StateCapacity::Reached(0.25)],
            vec![StateCapacity::Reached(0.4)],
            vec![StateCapacity::NotReached(0.1)],
        ];
        let def = FractileDef::Type7;
        let fits = fit_states(1, &caps, |_, eta| Some(0.2 / eta), def).unwrap();
        let f = &fits[0];
        assert_eq!(f.reached, 3);
        let all = [0.4, 0.8, 0.5, f64::INFINITY];
        assert_eq!(f.fractile, fractile_method(&all, def));
        assert_eq!(f.mle, max_likelihood(&[0.4, 0.8, 0.5], &[2.0]));
        assert_eq!(f.capacities, [0.4, 0.5, 0.8, f64::INFINITY]);
        assert!(fit_states(1, &caps, |k, eta| (k != 2).then_some(eta), def).is_none());
    }
}
