"""The damage-state shares pelicun computes for one component of a fragility
CSV at given demands (tests/engines.rs).

Usage: python pelicun_damage.py FRAGILITY.csv COMPONENT N DEMAND UNIT LEVEL [LEVEL ...]

DEMAND is pelicun's demand type (PGA, PFA, PFV, ...) and UNIT its unit (g,
cmps, ...). Prints one JSON object: {"levels": [...], "shares": [[P(DS=0),
..., P(DS=n)], ...]}, each share the fraction of N realisations in that
damage state, the demand fixed at the level (one demand location per level).
"""
import json
import sys

import numpy as np
import pandas as pd
from pelicun.assessment import Assessment

path, component, n = sys.argv[1], sys.argv[2], int(sys.argv[3])
kind, unit = sys.argv[4], sys.argv[5]
pgas = [float(v) for v in sys.argv[6:]]

a = Assessment({"PrintLog": False, "Seed": 42})
cols = pd.MultiIndex.from_tuples([(kind, str(i), "1") for i in range(len(pgas))])
demand = pd.DataFrame(np.tile(pgas, (n, 1)), columns=cols)
units = pd.DataFrame([[unit] * len(pgas)], columns=cols, index=["Units"])
a.demand.load_sample(pd.concat([units, demand.astype(object)]))
# pelicun offsets floor demands by -1 (its default DemandOffset for PFA and
# PFV): a component at location (story) k stands on floor k - 1, so the
# components of floor demands sit at 1..n against demands at 0..n-1.
first = 1 if kind in ("PFA", "PFV") else 0
marginals = pd.DataFrame(
    {
        "Units": ["ea"],
        "Location": [f"{first}--{first + len(pgas) - 1}"],
        "Direction": ["1"],
        "Theta_0": [1],
    },
    index=[component],
)
a.asset.load_cmp_model({"marginals": marginals})
a.asset.generate_cmp_sample()
a.damage.load_model_parameters([path], set(a.asset.list_unique_component_ids()))
a.damage.calculate()
ds = a.damage.ds_model.ds_sample
states = 1 + sum(1 for c in pd.read_csv(path).columns if c.endswith("-Family"))
shares = []
for i in range(len(pgas)):
    s = ds.loc[:, (component, str(first + i))].iloc[:, 0].to_numpy().astype(int)
    shares.append((np.bincount(s, minlength=states) / len(s)).tolist())
print(json.dumps({"levels": pgas, "shares": shares}))
