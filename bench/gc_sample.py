"""Samples random GarmentCode designs on its average body and writes their specifications.

    python3 bench/gc_sample.py GARMENTCODE_DIR OUT_DIR [COUNT] [SEED]

GARMENTCODE_DIR is a checkout of https://github.com/maria-korosteleva/GarmentCode (its
`pygarment` and `assets/`); it needs numpy, scipy, svgpathtools, svgwrite, pyyaml and
psutil (`pip install ...`). Their pattern pictures are not drawn, so cairosvg and
matplotlib may be missing. Each design is `MetaGarment` over `assets/design_params/
default.yaml` randomised as their own data-set sampler does, on `assets/bodies/
mean_all.yaml` (our `--body human`); designs their code refuses are skipped and said.
Then drape each, e.g.

    for f in OUT_DIR/*_specification.json; do
        target/release/cloth-sim scenario drape-pattern "$f" --frames 700 --quiet \\
            --out "out/gc/$(basename "$f" _specification.json)"
    done

Not part of `cargo test` (docs/garments.md, "Random GarmentCode designs").
"""

import random
import sys
import types
from pathlib import Path

if len(sys.argv) < 3:
    sys.exit(__doc__)
gc_dir, out = Path(sys.argv[1]).resolve(), Path(sys.argv[2])
count = int(sys.argv[3]) if len(sys.argv) > 3 else 10
seed = int(sys.argv[4]) if len(sys.argv) > 4 else 1

# Only their pictures need these; stand-ins let the rest import without them.
for name in ("cairosvg", "matplotlib", "matplotlib.pyplot"):
    try:
        __import__(name)
    except ImportError:
        sys.modules[name] = types.ModuleType(name)
sys.path.insert(0, str(gc_dir))

import pygarment as pyg  # noqa: E402
from assets.bodies.body_params import BodyParameters  # noqa: E402
from assets.garment_programs.meta_garment import MetaGarment  # noqa: E402
from pygarment.pattern.core import BasicPattern  # noqa: E402

random.seed(seed)
out.mkdir(parents=True, exist_ok=True)
body = BodyParameters(gc_dir / "assets/bodies/mean_all.yaml")
sampler = pyg.DesignSampler(gc_dir / "assets/design_params/default.yaml")
made = tries = 0
while made < count and tries < 10 * count:
    tries += 1
    name = f"random_{seed}_{tries}"
    try:
        pattern = MetaGarment(name, body, sampler.randomize()).assembly()
        pattern.name = name
        BasicPattern.serialize(pattern, str(out), to_subfolder=False)
    except Exception as e:  # their code refuses some combinations
        print(f"{name}: refused by GarmentCode ({type(e).__name__}: {str(e)[:80]})")
        continue
    made += 1
    panels = list(pattern.pattern["panels"])
    print(f"{name}: {len(panels)} panels ({', '.join(panels[:6])}{', ...' if len(panels) > 6 else ''})")
print(f"{made} designs of {tries} tried, in {out}")
