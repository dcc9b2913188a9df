"""The README's Python lines, run as written (`.ci/run` runs this file after
`pip install ./python`, the README's other Python line): every `python -c`
command of the README's ```sh blocks, in a scratch folder holding a copy of
targets/, must exit 0 and print what it computes."""

import re
import shutil
import subprocess
import sys


def readme_python_commands(root):
    text = (root / "README.md").read_text(encoding="utf-8")
    blocks = re.findall(r"```sh\n(.*?)```", text, flags=re.S)
    return [line.strip() for b in blocks for line in b.splitlines() if line.strip().startswith("python -c ")]


def test_readme_python_commands_run(root, scratch):
    commands = readme_python_commands(root)
    assert commands, "the README's Python quick start has a `python -c` line"
    shutil.copytree(root / "targets", scratch / "targets")
    for command in commands:
        code = re.match(r'python -c "(.*)"\s*(#.*)?$', command).group(1)
        out = subprocess.run([sys.executable, "-c", code], cwd=scratch, check=True, capture_output=True, text=True).stdout
        # The quick start prints the design's realised strength (s⁻¹): a positive number.
        assert float(out.strip()) > 0.0, out
