"""The LLM features, on any OpenAI-compatible chat endpoint (``docs/llm.md``).

* :mod:`legent_gym.llm.client`: :class:`ChatClient`, one client for any such endpoint
  (retries, JSON replies validated with pydantic); its public names are re-exported here.
* :mod:`legent_gym.llm.prompts`: the prompts, in one place and versioned.
* :mod:`legent_gym.llm.scene_from_text`: ``legent-gym generate --plan/--prompt``, a house
  from a scene plan an LLM writes for a description.
* :mod:`legent_gym.llm.task_generation`: ``legent-gym tasks generate``, an LLM's tasks for a
  scene, kept only if the experts complete them (``Legent/Custom-v0`` plays them).
* :mod:`legent_gym.llm.annotation`: ``legent-gym asset annotate``, a glTF asset's geometry
  computed and its semantics from a VLM, registered for the generator and the tasks.
"""

from legent_gym.llm.client import (
    MAX_REPLY_BYTES,
    OPENAI_BASE_URL,
    TRANSIENT_STATUS,
    CallLog,
    Calls,
    ChatClient,
    EndpointError,
    LLMError,
    ReplyError,
    describe_error,
    parse_reply,
    short,
)

__all__ = ["MAX_REPLY_BYTES", "OPENAI_BASE_URL", "TRANSIENT_STATUS", "CallLog", "Calls", "ChatClient",
           "EndpointError", "LLMError", "ReplyError", "describe_error", "parse_reply", "short"]
