"""The damage-state shares pelicun computes for one component of a fragility
CSV at given PGAs (tests/engines.rs).

Usage: python pelicun_damage.py FRAGILITY.csv COMPONENT N PGA [PGA ...]

Prints one JSON object: {"pga": [...], "shares": [[P(DS=0), ..., P(DS=n)], ...]},
each share the fraction of N realisations in that damage state, the demand
fixed at the PGA (one demand location per PGA level).
"""
import json
import sys

import numpy as np
import pandas as pd
from pelicun.assessment import Assessment

path, component, n = sys.argv[1], sys.argv[2], int(sys.argv[3])
pgas = [float(v) for v in sys.argv[4:]]

a = Assessment({"PrintLog": False, "Seed": 42})
cols = pd.MultiIndex.from_tuples([("PGA", str(i), "1") for i in range(len(pgas))])
demand = pd.DataFrame(np.tile(pgas, (n, 1)), columns=cols)
units = pd.DataFrame([["g"] * len(pgas)], columns=cols, index=["Units"])
a.demand.load_sample(pd.concat([units, demand.astype(object)]))
marginals = pd.DataFrame(
    {"Units": ["ea"], "Location": [f"0--{len(pgas) - 1}"], "Direction": ["1"], "Theta_0": [1]},
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
    s = ds.loc[:, (component, str(i))].iloc[:, 0].to_numpy().astype(int)
    shares.append((np.bincount(s, minlength=states) / len(s)).tolist())
print(json.dumps({"pga": pgas, "shares": shares}))
