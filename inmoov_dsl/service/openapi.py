"""The service's OpenAPI document (served at ``/api/openapi.json``); its limits are
given by the caller (``core``'s) or read where they are set, so they are written once."""

from __future__ import annotations

from typing import Any

from ..compiling.plan import MAX_GESTURE_DURATION
from .allowance import MAX_SOUNDS, MAX_SPEECH
from .work import BUDGET


def _answer(description: str, schema: str | None = None) -> dict[str, Any]:
    body = {"content": {"application/json": {"schema": {"$ref": f"#/components/schemas/"
                                                                f"{schema}"}}}}
    return {"description": description, **(body if schema else {})}


def document(version: str, max_body: int, max_loop: int) -> dict[str, Any]:
    """The OpenAPI 3.1 document of the service of ``version``: bodies of at most
    ``max_body`` bytes, at most ``max_loop`` passes."""
    errors = {"400": _answer(f"not a request the service takes (not JSON, an unknown "
                             f"field, a wrong type, over {max_body:,} bytes)", "BadRequest"),
              "401": _answer("a token is needed", "BadRequest"),
              "403": _answer("a request from another site, or an unknown Host",
                             "BadRequest"),
              "503": _answer("a board the request needs is not there", "BadRequest")}
    control = {"responses": {"200": _answer("done", "Accepted"), **errors}}
    return {
        "openapi": "3.1.0",
        "info": {"title": "inmoov-dsl service", "version": version,
                 "description": "Drive the hand: play library gestures and steps, stop, "
                                "relax, read the pose, follow events (docs/service.md)."},
        "paths": {
            "/api/gestures": {"get": {"summary": "the library as the service plays it",
                                      "responses": {"200": _answer("the gestures",
                                                                   "Gestures")}}},
            "/api/play": {"post": {
                "summary": "play a library gesture, steps, or a gesture of a text",
                "requestBody": {"required": True, "content": {"application/json": {
                    "schema": {"$ref": "#/components/schemas/Play"}}}},
                "responses": {"202": _answer("accepted: its id", "Accepted"),
                              "422": _answer(f"it does not compile (a gesture lasts at "
                                             f"most {MAX_GESTURE_DURATION:g} s; a request "
                                             f"says at most {MAX_SOUNDS} sounds, "
                                             f"{MAX_SPEECH:g} s in all), its check took "
                                             f"more than {BUDGET:g} s, or it would drive "
                                             "the robot's parts into each other (where "
                                             "and when)", "Problem"),
                              **errors, "503": _answer(
                                  "a board the request needs is not there, or the service "
                                  "stops", "BadRequest")}}},
            "/api/stop": {"post": {"summary": "CANCEL: the hand holds where it is, the "
                                              "queue is emptied", **control}},
            "/api/relax": {"post": {"summary": "the servos go limp", **control}},
            "/api/pose": {"get": {"summary": "what each board holds",
                                  "responses": {"200": _answer("the pose", "Pose")}}},
            "/api/view": {"get": {"summary": "where the hand is drawn in 3-D (null without "
                                             "the web extra)",
                                  "responses": {"200": {"description": "{\"url\": ...}"}}}},
            "/api/events": {"get": {"summary": "a WebSocket: one JSON object per event",
                                    "responses": {"101": {"description": "switching to "
                                                                         "WebSocket"}}}},
        },
        "components": {"schemas": _schemas(max_loop)},
    }


def _schemas(max_loop: int) -> dict[str, Any]:
    text = {"type": "string"}
    return {
        "Play": {"type": "object", "additionalProperties": False, "properties": {
            "gesture": {**text, "description": "a library gesture's name (with text: "
                        "which of its gestures; default: its only one)"},
            "steps": {**text, "description": "one line of .gest steps"},
            "text": {**text, "description": "a .gest file's text: its definitions over "
                     "the library's, no use line"},
            "side": {"enum": ["left", "right"]},
            "when": {"enum": ["now", "after"], "default": "now"},
            "loop": {"oneOf": [{"type": "boolean"},
                               {"type": "integer", "minimum": 1, "maximum": max_loop}]},
            "allow_contact": {"type": "boolean", "description": "play it though the "
                              "robot's parts meet (padded parts); default: the service's "
                              "--allow-contact"}},
            "oneOf": [{"required": ["steps"]}, {"required": ["text"]},
                      {"required": ["gesture"], "not": {"required": ["text"]}}]},
        "Accepted": {"type": "object", "properties": {"id": text, "warnings": {
            "type": "array", "items": {"type": "object"}}}},
        "BadRequest": {"type": "object", "properties": {"error": text, "hint": text}},
        "Problem": {"type": "object", "properties": {
            "error": text, "text": text, "diagnostics": {"type": "array", "items": {
                "type": "object", "properties": {
                    "severity": text, "message": text, "hint": text, "line": {},
                    "column": {}, "width": {}, "source": text, "text": text}}}}},
        "Gestures": {"type": "array", "items": {"type": "object", "properties": {
            "name": text, "file": text, "profile": text, "duration": {"type": "number"},
            "description": text}}},
        "Pose": {"type": "object", "properties": {"playing": {}, "servos": {
            "type": "object", "additionalProperties": {"type": "object", "properties": {
                "value": {"type": "integer"}, "moving": {"type": "boolean"}}}}}},
    }
