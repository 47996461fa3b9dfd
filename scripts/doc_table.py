#!/usr/bin/env python3
"""Puts a generated table into a doc between its markers, atomically.

    scripts/doc_table.py DOC NAME TABLE_FILE

replaces what lies between `<!-- NAME:begin -->` and `<!-- NAME:end -->` in DOC
with TABLE_FILE's text (the study scripts' tables: closed_loop.sh, photo_study.sh).
"""
import os
import sys

doc_path, name, table_path = sys.argv[1:4]
table = open(table_path).read()
doc = open(doc_path).read()
begin, end = f"<!-- {name}:begin -->", f"<!-- {name}:end -->"
if begin not in doc or end not in doc:
    sys.exit(f"{doc_path}: no {begin} ... {end} markers; add them where the table goes")
head, rest = doc.split(begin, 1)
_, tail = rest.split(end, 1)
tmp = doc_path + ".tmp"
open(tmp, "w").write(head + begin + "\n" + table + end + tail)
os.replace(tmp, doc_path)
