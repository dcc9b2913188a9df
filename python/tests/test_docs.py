"""docs/python.md's sweep table and the prose after it state what
docs/python/sweep.json holds: the table is `markdown_table()` of sweep.json
(docs/python/sweep_example.py writes both; the 9 designs are not re-run
here), and every number in the paragraph after the table is one the table
shows."""

import importlib.util
import json
import re


def example(root):
    spec = importlib.util.spec_from_file_location("sweep_example", root / "docs" / "python" / "sweep_example.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_sweep_table_is_generated_from_sweep_json(root):
    se = example(root)
    records = json.loads((root / "docs" / "python" / "sweep.json").read_text(encoding="utf-8"))
    assert len(records) == len(se.FRICTION) * len(se.LINEAR_XY)
    doc = (root / "docs" / "python.md").read_text(encoding="utf-8")
    assert se.doc_table(doc) == se.markdown_table(records), (
        "docs/python.md's sweep table differs from sweep.json: run `python docs/python/sweep_example.py --doc`"
    )


def test_prose_after_the_table_states_only_the_tables_numbers(root):
    se = example(root)
    doc = (root / "docs" / "python.md").read_text(encoding="utf-8")
    table = se.doc_table(doc)
    after = doc[doc.index(se.TABLE_END) + len(se.TABLE_END):]
    paragraph = after.strip().split("\n\n")[0]
    # Numbers in the table's cells (μ, limits, strengths, shape errors).
    cells = {c.strip().rstrip(" %") for line in table.splitlines()[2:] for c in line.split("|")}
    numbers = re.findall(r"\d+(?:\.\d+)?", paragraph.replace("s⁻¹", ""))
    stray = [n for n in numbers if n not in cells and n not in {"9"}]
    assert not stray, f"the paragraph after the sweep table states numbers the table does not show: {stray}"
