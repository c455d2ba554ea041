"""The sweep's table (every run's result.json, one row each, as CSV and JSON), its summary picture, and its
counts per status and per node (sweep.json)."""
import csv
import json
import math
import sys

import matplotlib

matplotlib.use("Agg")  # headless
import matplotlib.pyplot as plt  # noqa: E402

COLOURS = {"pass": "#2e9e44", "fail": "#d62728", "error": "#7f7f7f", "crash": "#000000", "timeout": "#9467bd",
           "never_started": "#ff7f0e", "lost": "#8c564b"}
MAX_METRIC_PANELS = 8


def row_of(index, values, status, run, starts):
    """One row: the cell, its verdict, where it ran and how often it began (`starts`: its runs' (cell, node,
    host, time)), every check's value and every metric, flattened to columns."""
    row = {"index": index}
    row.update({"axis:" + axis: value for axis, value in values.items()})
    result = run.get("result") or {}
    row.update({"status": status, "exit_code": run["exit_code"],
                "message": run.get("no_run") or result.get("message", ""), "wall_s": round(run["wall_s"], 4),
                "ended_s": round(run["ended_s"], 3), "host": run["host"], "node": run["node"],
                "attempts": len(starts), "began_on": " ".join(start[1] for start in starts)})
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


def node_table(rows, starts, nodes, alive_at_start, runs_s):
    """Per node that was alive when the sweep began or ran a cell: its address, CPUs, whether it was lost, the
    runs it gave (each cell counts once, on the node whose run counted), the runs it began, its runs per minute
    (from the sweep's start to its last run's end)."""
    table = []
    for node, state in nodes.items():
        gave = [row for row in rows if row["node"] == node and row["status"] != "never_started"]
        began = sum(1 for start in starts if start[1] == node)
        if node not in alive_at_start and not began:
            continue
        span = max([row["ended_s"] for row in gave], default=runs_s)
        table.append({"node_id": node, "address": state["address"], "cpus": state["cpus"], "alive": state["alive"],
                      "lost": node in alive_at_start and not state["alive"], "runs": len(gave), "began": began,
                      "runs_per_min": 60 * len(gave) / span if span > 0 else None})
    return table


def sweep_summary(rows, starts, nodes, alive_at_start, ray_start_s, runs_s):
    """sweep.json: the counts per status, the pace, each node's share, the nodes lost and the runs begun again."""
    statuses = [row["status"] for row in rows]
    table = node_table(rows, starts, nodes, alive_at_start, runs_s)
    return {"runs": len(rows), "passed": statuses.count("pass"), "failed": statuses.count("fail"),
            "other": len(rows) - statuses.count("pass") - statuses.count("fail"),
            "statuses": {status: statuses.count(status) for status in COLOURS if status in statuses},
            "ray_start_s": ray_start_s, "runs_s": runs_s,
            "runs_per_min": 60 * len(rows) / runs_s if runs_s > 0 else None,
            "nodes": table, "lost_nodes": [node["node_id"] for node in table if node["lost"]],
            "began_again": [{"index": row["index"], "began_on": row["began_on"].split()}
                            for row in rows if row["attempts"] > 1]}


def print_summary(name, summary, rows, results_path):
    print("sweep %s: %d runs, %d passed, %d failed, %d could not run or crashed, in %.1f s (%.0f runs/min; "
          "Ray started in %.1f s) on %d nodes, %d lost, %d runs begun again; %s" % (
              name, summary["runs"], summary["passed"], summary["failed"], summary["other"], summary["runs_s"],
              summary["runs_per_min"] or 0, summary["ray_start_s"], len(summary["nodes"]),
              len(summary["lost_nodes"]), len(summary["began_again"]), results_path))
    for row in rows:
        if row["status"] in ("never_started", "lost"):
            print("  cell %d: %s: %s" % (row["index"], row["status"].replace("_", " "), row["message"]),
                  file=sys.stderr)
        elif row["status"] != "pass" and row["status"] != "fail":
            print("  cell %d: %s (exit code %s): %s" % (row["index"], row["status"], row["exit_code"],
                                                       (row.get("log_tail") or "").strip()[-300:]), file=sys.stderr)
