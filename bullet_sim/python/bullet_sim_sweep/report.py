"""The sweep's table (every run's result.json, one row each, as CSV and JSON) and its summary picture."""
import csv
import json
import math

import matplotlib

matplotlib.use("Agg")  # headless
import matplotlib.pyplot as plt  # noqa: E402

COLOURS = {"pass": "#2e9e44", "fail": "#d62728", "error": "#7f7f7f", "crash": "#000000", "timeout": "#9467bd"}
MAX_METRIC_PANELS = 8


def row_of(index, values, status, run):
    """One row: the cell, its verdict, every check's value and every metric, flattened to columns."""
    row = {"index": index}
    row.update({"axis:" + axis: value for axis, value in values.items()})
    result = run.get("result") or {}
    row.update({"status": status, "exit_code": run["exit_code"], "message": result.get("message", ""),
                "wall_s": round(run["wall_s"], 4), "host": run["host"]})
    timing = result.get("timing") or {}
    row["rtf"] = timing.get("rtf")
    for number, check in enumerate(result.get("checks", [])):
        name = "check:%d:%s:%s" % (number, check["type"], check["robot"])
        row[name + ":passed"] = check["passed"]
        row[name + ":value"] = check["value"]
    for robot, metrics in (result.get("metrics") or {}).items():
        for metric, value in metrics.items():
            row["metric:%s:%s" % (robot, metric)] = value
    if status not in ("pass", "fail"):
        row["log_tail"] = run.get("log") or ""
    return row


def write_table(rows, csv_path, json_path):
    columns = []
    for row in rows:
        columns += [column for column in row if column not in columns]
    with open(csv_path, "w", newline="") as file:
        writer = csv.DictWriter(file, fieldnames=columns)
        writer.writeheader()
        for row in rows:
            writer.writerow({column: row.get(column, "") for column in columns})
    with open(json_path, "w") as file:
        json.dump(rows, file, indent=2)
        file.write("\n")


def _grid(ax, rows, axes):
    """Pass/fail per cell: the last axis across, every other axis combined down."""
    last = axes[-1] if axes else None
    across = list(dict.fromkeys(row.get("axis:" + last) for row in rows)) if last else [None]
    down_key = lambda row: ", ".join(str(row.get("axis:" + a)) for a in axes[:-1]) or "all"  # noqa: E731
    down = list(dict.fromkeys(down_key(row) for row in rows))
    for row in rows:
        x = across.index(row.get("axis:" + last)) if last else 0
        y = down.index(down_key(row))
        ax.add_patch(plt.Rectangle((x, y), 0.92, 0.92, color=COLOURS.get(row["status"], "#ffffff")))
    ax.set_xlim(-0.1, len(across))
    ax.set_ylim(len(down), -0.1)
    ax.set_xticks([i + 0.46 for i in range(len(across))])
    ax.set_xticklabels([str(v) for v in across], rotation=45, ha="right", fontsize=7)
    ax.set_yticks([i + 0.46 for i in range(len(down))])
    ax.set_yticklabels(down, fontsize=7)
    ax.set_xlabel(last or "")
    ax.set_ylabel(", ".join(axes[:-1]))
    counts = {s: sum(1 for r in rows if r["status"] == s) for s in COLOURS}
    ax.set_title("  ".join("%s %d" % (s, n) for s, n in counts.items() if n), fontsize=9)


def _numbers(rows, column):
    values = []
    for row in rows:
        value = row.get(column)
        if isinstance(value, (int, float)) and not isinstance(value, bool) and math.isfinite(value):
            values.append(value)
    return values


def write_summary(rows, axes, title, path):
    """A picture: the pass/fail grid, then a histogram of each metric and of the wall time per run."""
    metrics = sorted({c for row in rows for c in row if c.startswith("metric:")})
    columns = [c for c in metrics if len(set(_numbers(rows, c))) > 0][:MAX_METRIC_PANELS] + ["wall_s"]
    panels = 1 + len(columns)
    across = min(3, panels)
    down = math.ceil(panels / across)
    figure, grid = plt.subplots(down, across, figsize=(4.2 * across, 3.4 * down), squeeze=False)
    flat = [ax for line in grid for ax in line]
    _grid(flat[0], rows, axes)
    for ax, column in zip(flat[1:], columns):
        # Stacked by status: which values the passing runs had, and which the others.
        groups = [(s, _numbers([r for r in rows if r["status"] == s], column)) for s in COLOURS]
        groups = [(s, values) for s, values in groups if values]
        every = [v for _, values in groups for v in values]
        ax.hist([values for _, values in groups], bins=min(20, max(1, len(set(every)))), stacked=True,
                color=[COLOURS[s] for s, _ in groups], label=[s for s, _ in groups])
        ax.set_title(column.replace("metric:", ""), fontsize=9)
        ax.tick_params(labelsize=7)
    for ax in flat[1 + len(columns):]:
        ax.axis("off")
    figure.suptitle(title, fontsize=11)
    figure.tight_layout()
    figure.savefig(path, dpi=90)
    plt.close(figure)
