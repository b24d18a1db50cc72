#!/usr/bin/env python3
"""Writes fuzz/scene.dict, the libFuzzer dictionary of fuzz_scene: every
parameter name, choice and plugin name of share/schema/suffuse-schema.json
(the output of `suffuse schema`), and every key and string value of the
example scenes. Run again when the schema changes."""
import json
import pathlib

root = pathlib.Path(__file__).resolve().parent.parent
words = set()


def add_schema_params(params):
    for p in params:
        words.add(p["name"])
        for c in p.get("choices", []):
            words.add(c)


schema = json.loads((root / "share/schema/suffuse-schema.json").read_text())
for section in schema["core"].values():
    add_schema_params(section.get("parameters", []))
for name, plugin in schema["plugins"].items():
    words.add(name)
    add_schema_params(plugin.get("parameters", []))


def walk(value):
    if isinstance(value, dict):
        for k, v in value.items():
            words.add(k)
            walk(v)
    elif isinstance(value, list):
        for v in value:
            walk(v)
    elif isinstance(value, str) and len(value) <= 40:
        words.add(value)


for scene in sorted((root / "share/scenes").glob("*.json")):
    walk(json.loads(scene.read_text()))

lines = ["# libFuzzer dictionary for fuzz_scene, written by fuzz/make_dict.py: do not edit."]
# Each word as a JSON string, quotes included. "plugin_paths" is left out:
# fuzz_scene skips scenes that name plugin directories.
words.discard("plugin_paths")


def entry(text):
    return '"' + text.replace("\\", "\\\\").replace('"', '\\"') + '"'


lines += [entry(json.dumps(w)) for w in sorted(words) if w]
# JSON tokens that mutations rarely produce whole.
lines += [entry(t) for t in ["true", "false", "null", "1e308", "-0", "1e-320", "NaN", '":', "[]", "{}"]]
(root / "fuzz/scene.dict").write_text("\n".join(lines) + "\n")
print(len(lines) - 1, "entries")
