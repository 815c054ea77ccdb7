"""XMPP transport: modules in separate processes talk through Prosody or ejabberd.

Configure a module with::

    comm:
      class: nightcrew.comm.xmpp.XmppComm
      jid: camera@observatory.local
      password: ${CAMERA_PASSWORD}
      server: 127.0.0.1:5222        # optional: the JID's domain, port 5222
      ca_file: /srv/xmpp/certs/observatory.local.crt   # optional: trust a self-signed server

The wire protocol is in docs/protocol.md. slixmpp is imported only when a comm opens.
"""

from nightcrew.comm.xmpp._comm import XmppComm
from nightcrew.comm.xmpp._errors import XmppAuthError
from nightcrew.comm.xmpp._settings import XmppSettings, is_loopback, parse_jid

__all__ = ["XmppAuthError", "XmppComm", "XmppSettings", "is_loopback", "parse_jid"]
