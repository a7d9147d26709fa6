"""Median ATE RMSE and frames lost per scenario and mode, from the summary.json files of runs named
<scenario>__<mode>__<run> (scripts/slam-table.sh), as Markdown tables."""
import json
import pathlib
import statistics
import sys


def main():
    runs = pathlib.Path(sys.argv[1])
    split = sys.argv.index("--")
    scenarios, modes = sys.argv[2:split], sys.argv[split + 1:]
    results = {}
    for summary in runs.glob("*/summary.json"):
        scenario, mode, _ = summary.parent.name.split("__")
        data = json.loads(summary.read_text())
        ate = data.get("evaluation", {}).get("ate", {}).get("error_m", {}).get("rmse")
        results.setdefault((scenario, mode), []).append((ate, data["lost"] + data["before_initialization"]))

    def cell(key):
        values = results.get(key, [])
        if not values:
            return "–"
        ates = [a for a, _ in values if a is not None]
        lost = [l for _, l in values]
        text = f"{statistics.median(ates):.4f}" if ates else "no pose"
        if max(lost) > 0:
            text += f", lost {min(lost)}–{max(lost)}" if min(lost) != max(lost) else f", lost {lost[0]}"
        return text + (f" ({len(values)})" if len(values) != max_runs else "")

    max_runs = max((len(v) for v in results.values()), default=0)
    print(f"ATE RMSE (m), median of {max_runs} runs (fewer where shown in brackets); frames lost or before the map")
    print("started, range over the runs, where any\n")
    print("| scenario | " + " | ".join(f"`{m}`" for m in modes) + " | `_static` control, `none` |")
    print("|---|" + "---|" * (len(modes) + 1))
    for s in scenarios:
        print(f"| {s} | " + " | ".join(cell((s, m)) for m in modes) + f" | {cell((s + '_static', 'none'))} |")
    medians = {m: [statistics.median([a for a, _ in results[(s, m)] if a is not None])
                   for s in scenarios if results.get((s, m)) and any(a is not None for a, _ in results[(s, m)])]
               for m in modes}
    print("| median over the six | " + " | ".join(
        f"{statistics.median(v):.4f}" if len(v) == len(scenarios) else "–" for v in medians.values()) + " | |")


if __name__ == "__main__":
    main()
