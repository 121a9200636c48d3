"""Sofa.Helper: msg_info, msg_warning, msg_error, msg_deprecated, msg_fatal, MessageHandler
(penalty's SofaPython3, penalty/sofa_api/helper.py)."""
from penalty.sofa_api.helper import (MessageHandler, msg_deprecated, msg_error, msg_fatal, msg_info,  # noqa: F401
                                     msg_warning)


def __getattr__(name):
    if name.startswith("__"):
        raise AttributeError(name)
    raise AttributeError(f"Sofa.Helper.{name} is not available in penalty's SofaPython3 (see docs/python.md)")
