"""Edits of a WISH model file for tests, sealed as the C++ writer seals (core/classify/model_file.cpp): the seal is the
SHA-256 of nlohmann's compact dump of the payload, whose number tokens are those of the file itself (written with
dump(1)), so the compact text is the file's payload text without the whitespace outside strings. Editing the text
(not a json.loads/json.dumps round trip, which may print doubles differently) keeps every other token as written.
"""
import hashlib
import json


def _compact(text):
    out, in_string, escaped = [], False, False
    for ch in text:
        if in_string:
            out.append(ch)
            if escaped:
                escaped = False
            elif ch == "\\":
                escaped = True
            elif ch == '"':
                in_string = False
        elif ch not in " \n\t\r":
            in_string = ch == '"'
            out.append(ch)
    return "".join(out)


def _payload_text(compact):
    start = compact.index('"payload":') + len('"payload":')
    depth, in_string, escaped = 0, False, False
    for i in range(start, len(compact)):
        ch = compact[i]
        if in_string:
            if escaped:
                escaped = False
            elif ch == "\\":
                escaped = True
            elif ch == '"':
                in_string = False
        elif ch == '"':
            in_string = True
        elif ch == "{":
            depth += 1
        elif ch == "}":
            depth -= 1
            if depth == 0:
                return compact[start:i + 1]
    raise ValueError("no payload object")


def payload_seal(text):
    """The seal of a model file's text as the C++ loader computes it."""
    return hashlib.sha256(_payload_text(_compact(text)).encode("utf-8")).hexdigest()


# nlohmann's objects print their keys sorted (bytewise); "A..." sorts before every key a model file has ("C" of the
# SVM is the only upper-case one), so the key added first keeps the text in the order the loader's dump has.
UNKNOWN_KEY = "A_new_setting"


def with_unknown_key(source, target, anchor='"map": {', key=UNKNOWN_KEY):
    """Copies the model file `source` to `target` with `"key": 1` added as the first member of the object that opens
    at the first `anchor` (by default payload.recipe.map), re-sealed so that only the unknown key is wrong. `key` must
    sort before the object's other keys (the default does)."""
    with open(source, encoding="utf-8") as f:
        text = f.read()
    old_seal = json.loads(text)["payload_sha256"]
    at = text.index(anchor) + len(anchor)
    text = text[:at] + f'\n    "{key}": 1,' + text[at:]
    text = text.replace(old_seal, payload_seal(text))
    with open(target, "w", encoding="utf-8") as f:
        f.write(text)
