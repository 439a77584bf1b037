"""The language server as the tests start it (``gestc lsp`` on a pipe) and pytest-lsp's
client on it, initialized as VS Code initializes: the ``client`` fixture (conftest.py
offers it; a module with a client of its own names it the same)."""

from __future__ import annotations

import sys

import pytest_lsp
from lsprotocol import types as lsp
from pytest_lsp import ClientServerConfig, LanguageClient, client_capabilities

SERVER = [sys.executable, "-m", "inmoov_dsl.cli.gestc", "lsp"]


@pytest_lsp.fixture(config=ClientServerConfig(server_command=SERVER))
async def client(lsp_client: LanguageClient):
    await lsp_client.initialize_session(lsp.InitializeParams(
        capabilities=client_capabilities("visual-studio-code")))
    yield
    await lsp_client.shutdown_session()
