//! FEMA P-58's unanchored contents that are rocking blocks (pure data): the
//! bookcases and filing cabinets E.20.22.102a–125a of FEMA P-58's
//! component database, as SimCenter's Damage and Loss Model Library
//! carries it (simcenter-dlml 3.2, `seismic/building/component/FEMA P-58
//! 2nd Edition`, `fragility.csv` and `fragility.json`): one damage state,
//! "falls over", lognormal in Peak Floor Velocity (m/s) with β = 0.5,
//! non-directional, demand offset 0. The sizes are the descriptions'
//! ("Bookcase is 12-5/8" deep x 56" tall"); the depth is the direction an
//! item topples in. The library's notes say the median "is calculated as a
//! function of the aspect ratio ... and the building period, T"; the
//! formula is not given with the data, and each row holds one median.

/// One FEMA P-58 contents component.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Content {
    /// The component id (`E.20.22.104a`).
    pub id: &'static str,
    /// Its name in the library.
    pub name: &'static str,
    /// Depth and height (inches), as described.
    pub depth_in: f64,
    pub height_in: f64,
    /// FEMA's median PFV at falling over (m/s) and its β.
    pub median_mps: f64,
    pub beta: f64,
}

const INCH_M: f64 = 0.0254;

impl Content {
    /// Half the depth (m): the block's b.
    pub fn b_m(&self) -> f64 {
        0.5 * self.depth_in * INCH_M
    }

    /// Half the height (m): the block's h.
    pub fn h_m(&self) -> f64 {
        0.5 * self.height_in * INCH_M
    }
}

/// The nine, in the library's order.
pub const FEMA_P58: [Content; 9] = [
    content("E.20.22.102a", "Bookcase, 2 shelves", 12.625, 29.0, 0.724),
    content("E.20.22.103a", "Bookcase, 3 shelves", 12.625, 41.0, 0.493),
    content("E.20.22.104a", "Bookcase, 4 shelves", 12.625, 56.0, 0.361),
    content("E.20.22.105a", "Bookcase, 5 shelves", 12.625, 71.0, 0.29),
    content("E.20.22.106a", "Bookcase, 6 shelves", 12.625, 81.25, 0.251),
    content(
        "E.20.22.112a",
        "Vertical filing cabinet, 2 drawers",
        15.0,
        24.0,
        1.229,
    ),
    content(
        "E.20.22.114a",
        "Vertical filing cabinet, 4 drawers",
        15.0,
        52.0,
        0.498,
    ),
    content(
        "E.20.22.124a",
        "Lateral filing cabinet, 2 drawers",
        18.6,
        52.5,
        0.688,
    ),
    content(
        "E.20.22.125a",
        "Lateral filing cabinet, 4 drawers",
        18.6,
        67.75,
        0.526,
    ),
];

const fn content(
    id: &'static str,
    name: &'static str,
    depth_in: f64,
    height_in: f64,
    median_mps: f64,
) -> Content {
    Content {
        id,
        name,
        depth_in,
        height_in,
        median_mps,
        beta: 0.5,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The 4-shelf bookcase: 12-5/8 in = 0.320675 m deep, 56 in = 1.4224 m
    /// tall (hand-worked).
    #[test]
    fn sizes_are_the_descriptions_in_metres() {
        let c = FEMA_P58[2];
        assert!((c.b_m() - 0.160_337_5).abs() < 1e-12);
        assert!((c.h_m() - 0.7112).abs() < 1e-12);
        // Stockier items stand longer in FEMA's rows, as in physics.
        assert!(FEMA_P58[..5]
            .windows(2)
            .all(|w| w[0].median_mps > w[1].median_mps));
    }
}
