"""The sink designed at three friction values x three shaker limits (docs/python.md).

Run from the repository root, with the package installed (`pip install ./python`)
and, for the plot, matplotlib:

    python docs/python/sweep_example.py            # on a 2-worker Dask LocalCluster
    python docs/python/sweep_example.py --serial   # the same designs, one after another
    python docs/python/sweep_example.py --plot     # only redraw the plot from sweep.json
    python docs/python/sweep_example.py --doc      # only rewrite docs/python.md's table from sweep.json

Writes docs/python/sweep.json (the realised measures of every design),
docs/python/sweep.svg (realised strength and shape error against friction, one
line per shaker limit) and the table in docs/python.md between its two
`sweep table` markers (python/tests/test_docs.py checks that table equals
`markdown_table()` of sweep.json). Each design is `platefield design targets/sink.json`
(method auto: the sequenced and the synthesized candidates, and the mix when
both are POOR, each played, the best kept) with the target's friction and
shaker limits set.
"""

import json
import sys

import platefield

FRICTION = [0.15, 0.3, 0.6]
# Peak plate-centre linear acceleration allowed along x and y (m/s²). Along
# z 0.11 m/s², just above the paper's envelope (0.1092 m/s², the centripetal
# term of the LineSink's rotation): 0.109 would leave the sequenced design
# without its LineSinks. The angular limits are the envelope's (218.4, 218.4,
# 9055 rad/s²).
LINEAR_XY = [15.0, 30.0, 45.28]
SHAKER = [{"linear": [a, a, 0.11]} for a in LINEAR_XY]


def rows(records):
    """One row per design: its friction, limit and realised measures."""
    out = []
    for r in records:
        played = r["schedule"]["played"]
        out.append({
            "friction": r["friction"],
            "linear_xy_limit_m_s2": r["shaker"]["linear"][0],
            "kept": played["method"],
            "predicted_strength_per_s": played["predicted_strength"],
            "realised_strength_per_s": played["realised_strength"],
            "realised_shape_error": played["realised_shape_error"],
            "poor": played["poor"],
        })
    return out


# The lines around the generated table in docs/python.md.
TABLE_START = "<!-- sweep table: generated from docs/python/sweep.json by docs/python/sweep_example.py -->"
TABLE_END = "<!-- end of sweep table -->"


def markdown_table(records):
    """The markdown table of sweep.json's rows, one line per design."""
    lines = [
        "| μ | limit on \\|a_x\\|, \\|a_y\\| (m/s²) | kept | predicted strength (s⁻¹) "
        "| realised strength (s⁻¹) | realised shape error | |",
        "|---|---|---|---|---|---|---|",
    ]
    for r in records:
        lines.append(
            f"| {r['friction']:g} | {r['linear_xy_limit_m_s2']:g} | {r['kept']} "
            f"| {r['predicted_strength_per_s']:.2f} | {r['realised_strength_per_s']:.2f} "
            f"| {100 * r['realised_shape_error']:.1f} % | {'POOR' if r['poor'] else ''} |"
        )
    return "\n".join(lines) + "\n"


def doc_table(text):
    """The generated table in the text of docs/python.md (between the markers)."""
    start = text.index(TABLE_START) + len(TABLE_START) + 1
    return text[start:text.index(TABLE_END, start)]


def write_doc(records, path="docs/python.md"):
    """Replace the table between the markers in docs/python.md by markdown_table(records)."""
    with open(path, encoding="utf-8") as f:
        text = f.read()
    old = doc_table(text)
    start = text.index(TABLE_START) + len(TABLE_START) + 1
    text = text[:start] + markdown_table(records) + text[start + len(old):]
    with open(path, "w", encoding="utf-8") as f:
        f.write(text)


def plot(table, path):
    import matplotlib

    matplotlib.use("svg")
    matplotlib.rcParams["svg.hashsalt"] = "platefield"  # the same bytes every run
    import matplotlib.pyplot as plt

    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(9, 3.9))
    for limit in LINEAR_XY:
        sel = [r for r in table if r["linear_xy_limit_m_s2"] == limit]
        mu = [r["friction"] for r in sel]
        label = f"|a_x|, |a_y| ≤ {limit:g} m/s²"
        for ax, key, scale in ((ax1, "realised_strength_per_s", 1), (ax2, "realised_shape_error", 100)):
            (line,) = ax.plot(mu, [scale * r[key] for r in sel], "o-", label=label if ax is ax1 else None)
            poor = [r for r in sel if r["poor"]]
            ax.plot([r["friction"] for r in poor], [scale * r[key] for r in poor], "o",
                    ms=11, mfc="none", mec=line.get_color(),
                    label="POOR (shape error > 20 %)" if ax is ax1 and limit == LINEAR_XY[-1] else None)
    ax1.set(xlabel="friction μ", ylabel="realised strength (1/s)", title="sink: realised strength")
    ax2.set(xlabel="friction μ", ylabel="realised shape error (%)", title="realised shape error")
    ax2.axhline(20, color="grey", lw=0.8, ls="--")
    ax2.text(FRICTION[0], 20.5, "POOR above 20 %", color="grey", fontsize=8)
    fig.legend(loc="lower center", ncol=4, fontsize=8, frameon=False)
    fig.tight_layout(rect=(0, 0.08, 1, 1))
    fig.savefig(path, metadata={"Date": None, "Creator": None})


def main():
    if "--plot" in sys.argv or "--doc" in sys.argv:
        with open("docs/python/sweep.json", encoding="utf-8") as f:
            records = json.load(f)
        if "--plot" in sys.argv:
            plot(records, "docs/python/sweep.svg")
        if "--doc" in sys.argv:
            write_doc(records)
        return
    targets = ["targets/sink.json"]
    if "--serial" in sys.argv:
        records = platefield.sweep(targets, friction=FRICTION, shaker=SHAKER)
    else:
        from distributed import Client, LocalCluster

        with LocalCluster(n_workers=2, threads_per_worker=1) as cluster, Client(cluster) as client:
            records = platefield.sweep(targets, client=client, friction=FRICTION, shaker=SHAKER)
    table = rows(records)
    with open("docs/python/sweep.json", "w", encoding="utf-8") as f:
        json.dump(table, f, indent=1)
        f.write("\n")
    for r in table:
        print(json.dumps(r))
    write_doc(table)
    try:
        plot(table, "docs/python/sweep.svg")
    except ImportError:
        print("matplotlib not installed: no plot")


if __name__ == "__main__":
    main()
