"""python -m benchmarks [SUITE ...] [--repeat N] [--quick] [--out DIR]

Runs the named suites (default: all), prints a table and writes DIR/SUITE.json.
"""

from __future__ import annotations

import argparse
import importlib
import sys
from pathlib import Path

from illusio.core.technique import techniques

from .runner import print_table, write_results

#: each technique's suites (core.technique: ``benchmarks``) in the registry's order, then those of
#: the whole package (the protocol's overheads, the viewer, batch jobs)
SUITES = list(
    dict.fromkeys(
        [s for t in techniques().values() for s in t.benchmarks]
        + ["protocol", "viewer", "batch", "scene_files", "mgf_scenes", "svg_strokes"]
    )
)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(prog="python -m benchmarks", description=__doc__)
    parser.add_argument("suites", nargs="*", default=SUITES, help=f"suites to run: {', '.join(SUITES)}")
    parser.add_argument("--repeat", type=int, default=10, help="timed runs per case (after 2 warm-up runs)")
    parser.add_argument("--quick", action="store_true", help="small sizes, for a smoke run")
    parser.add_argument("--out", type=Path, default=Path("benchmarks/out"), help="folder for the JSON files")
    args = parser.parse_args(argv)
    unknown = set(args.suites) - set(SUITES)
    if unknown:
        print(
            f"benchmarks: unknown suite(s) {', '.join(sorted(unknown))}; choose from {', '.join(SUITES)}",
            file=sys.stderr,
        )
        return 2
    from illusio.core import Context, IllusioError

    try:
        ctx = Context()
    except IllusioError as exc:
        print(f"benchmarks: {exc.one_line()}", file=sys.stderr)
        return 2
    for suite in args.suites:
        module = importlib.import_module(f"benchmarks.{suite}")
        timings, ratios = module.run(ctx, args.repeat, args.quick)
        print(f"== {suite} on {ctx.info()['renderer']}")
        print_table(timings, ratios)
        write_results(args.out / f"{suite}.json", suite, ctx, timings, ratios)
        print(f"wrote {args.out / f'{suite}.json'}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
