// The operator panel's way in: the token from the page's address, and what the node's
// /whoami says of it, judged into what the panel does next. Of the page, only the address and
// the tab's stored token are touched here.
'use strict';

const PanelAccess = (function () {
  // A node with credentials lets the panel in with an operator's token, given in the page's
  // address after `#token=` (the part after `#` never leaves the browser). It is read once and
  // taken out of the address at once, so that it is not left in the address bar, the history
  // or a screenshot; the tab keeps it (sessionStorage) so that a reload still connects.
  const TOKEN = /(?:^#|&)token=([A-Za-z0-9._~-]+)/;
  const TOKEN_KEY = 'cooperation-panel-token';

  function takeToken() {
    const match = TOKEN.exec(location.hash);
    if (match) {
      try { sessionStorage.setItem(TOKEN_KEY, match[1]); } catch (_) { /* storage off */ }
      history.replaceState(null, '', location.pathname + location.search);
      return match[1];
    }
    try { return sessionStorage.getItem(TOKEN_KEY); } catch (_) { return null; }
  }

  function forgetToken() {
    try { sessionStorage.removeItem(TOKEN_KEY); } catch (_) { /* storage off */ }
  }

  // Asks the node who `token` makes this panel, without taking a connection's place: the
  // answer, the refusal (its status, text and Retry-After), or nothing from a node that does
  // not answer.
  async function whoami(token) {
    const headers = token ? { Authorization: `Bearer ${token}` } : {};
    let response;
    try {
      response = await fetch('/whoami', { headers, cache: 'no-store' });
    } catch (_) {
      return { kind: 'down' };
    }
    const text = (await response.text().catch(() => '')).trim();
    if (response.ok) {
      try {
        return { kind: 'answer', answer: JSON.parse(text) };
      } catch (_) {
        return { kind: 'refused', status: response.status, text: 'an answer that is not JSON' };
      }
    }
    const retry = Number(response.headers.get('retry-after'));
    return { kind: 'refused', status: response.status, text, retry: Number.isFinite(retry) && retry > 0 ? retry : null };
  }

  // What to do after `who` (whoami's result) for `token` on `host`: `open` a connection with
  // the answer, `retry` (after `delay` ms, or the backoff's next step) or stop, `refused`; with
  // the text that says why, and the role the node gave, if it gave one.
  function judge(who, token, host) {
    const again = `open it again at http://${host}/#token=… with an operator's token`;
    if (who.kind === 'down') return { action: 'retry', text: `Not connected: the node at ${host} does not answer` };
    if (who.kind === 'refused') {
      if (who.status === 401 && !token) {
        return { action: 'refused', text: `Not connected: this node lets in only a credential; ${again.replace('open it again', 'open the panel')}` };
      }
      if (who.status === 401) {
        // A wrong token stays wrong: it is forgotten, and not tried again (each try would be
        // counted as a guess).
        forgetToken();
        return { action: 'refused', text: `Not connected: the token this panel was opened with is not one of this node's credentials; ${again}` };
      }
      if (who.status === 429) {
        return { action: 'retry', text: 'Not connected: too many wrong tokens from this address, which is locked out for now', delay: (who.retry || 1) * 1000 };
      }
      return { action: 'retry', text: `Not connected: the node refused (HTTP ${who.status}: ${who.text || 'no reason given'})` };
    }
    const answer = who.answer;
    if (answer.open >= answer.places) {
      const text = answer.credential
        ? `Not connected: credential "${answer.credential}" has all ${answer.places} of its connections open, the most it may have; close a panel or client that uses it`
        : `Not connected: the node serves all ${answer.places} clients it may at once`;
      return { action: 'retry', text, role: answer.role };
    }
    return { action: 'open', answer, role: answer.role };
  }

  return { TOKEN, takeToken, whoami, judge };
})();
