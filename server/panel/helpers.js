// The operator panel's small helpers: UUIDs as the node writes them, names and distances as
// the panel shows them, and the few DOM writes that touch an element only when it changes (so
// that nothing under the pointer is redrawn for nothing). No state; nothing here talks to the
// node.
'use strict';

const PanelHelpers = (function () {
  // A UUID's bytes: this node writes a list of numbers; rosbridge writes base64.
  function uuidBytes(uuid) {
    const value = uuid && uuid.uuid;
    if (Array.isArray(value)) return value.slice();
    if (typeof value === 'string') return Array.from(atob(value), (c) => c.charCodeAt(0));
    return [];
  }

  function hex(bytes) {
    return bytes.map((b) => b.toString(16).padStart(2, '0')).join('');
  }

  function formatUuid(h) {
    return h.length === 32
      ? `${h.slice(0, 8)}-${h.slice(8, 12)}-${h.slice(12, 16)}-${h.slice(16, 20)}-${h.slice(20)}`
      : h;
  }

  function moduleName(behavior, sequence) {
    return sequence ? `${behavior} / ${sequence}` : behavior;
  }

  // A distance as the node wrote it: a number, or null for a non-finite one.
  function metres(value) {
    return typeof value === 'number' ? `${value.toFixed(1)} m` : '—';
  }

  function sortKey(value) {
    return typeof value === 'number' ? value : Infinity;
  }

  function setText(element, text) {
    if (element.textContent !== text) element.textContent = text;
  }

  function setAttr(element, name, value) {
    if (element.getAttribute(name) !== value) element.setAttribute(name, value);
  }

  function el(tag, attributes, children) {
    const element = document.createElement(tag);
    for (const [name, value] of Object.entries(attributes || {})) element.setAttribute(name, value);
    for (const child of children || []) {
      element.append(child);
    }
    return element;
  }

  return { uuidBytes, hex, formatUuid, moduleName, metres, sortKey, setText, setAttr, el };
})();
