// The operator panel: the scenes of both factor streams, those waiting for the operator first
// (counted in the header and the page's title, each saying why), then nearest first, with the
// four operator decisions, each scene's merged decision, age and whether its module reports it
// unsafe (from the node's /cooperation/scenes); the modules' policies as switches; the node's
// answers, with a history. Everything shown comes from the node: a decision or a policy is
// drawn from the next publication or get_policies, never assumed from a click. Overriding a
// module that reports a scene unsafe takes a second, confirming click, and the row says so for
// as long as the override stands; a policy switch takes a confirmation. While the pointer is
// over the scenes, no row moves. Before connecting, the panel asks the node who its token
// makes it (/whoami), so that a wrong token, a lockout, a full credential or a module's token
// is said as such, and a module's token gets no operator controls.
'use strict';

(function () {
  const DECISION = { UNKNOWN: 0, DEACTIVATE: 1, ACTIVATE: 2, AUTONOMOUS: 3, UNDECIDED: 4 };
  const DECISION_NAME = { 0: 'unknown', 1: 'deactivate', 2: 'activate', 3: 'autonomous', 4: 'none' };
  // The operator's choices, in the order of the buttons.
  const CHOICES = [
    { decision: DECISION.DEACTIVATE, label: 'Deactivate' },
    { decision: DECISION.ACTIVATE, label: 'Activate' },
    { decision: DECISION.AUTONOMOUS, label: 'Autonomous' },
    { decision: DECISION.UNDECIDED, label: 'None' },
  ];
  const POLICY = { OPTIONAL: 1, REQUIRED: 2 };
  const STEERING_DIRECTION = { 1: 'left', 2: 'right', 3: 'straight' };
  const SERVICE = {
    setCommands: ['/api/planning/cooperation/set_commands', 'autoware_adapi_v1_msgs/srv/SetCooperationCommands'],
    setPolicies: ['/api/planning/cooperation/set_policies', 'autoware_adapi_v1_msgs/srv/SetCooperationPolicies'],
    getPolicies: ['/api/planning/cooperation/get_policies', 'autoware_adapi_v1_msgs/srv/GetCooperationPolicies'],
  };
  const TOPIC = {
    velocity: ['/api/planning/velocity_factors', 'autoware_adapi_v1_msgs/msg/VelocityFactorArray'],
    steering: ['/api/planning/steering_factors', 'autoware_adapi_v1_msgs/msg/SteeringFactorArray'],
  };
  const SCENES_TOPIC = ['/cooperation/scenes', 'cooperation_server/msg/SceneArray'];
  // A scene its module has not reported for this long is shown stale.
  const STALE_MS = 1000;
  // A confirming click must come within this time of the first.
  const CONFIRM_MS = 5000;
  const HISTORY_LENGTH = 30;
  // A call the node has not answered in this time is reported as unanswered.
  const CALL_TIMEOUT_MS = 5000;
  const POLICY_REFRESH_MS = 5000;

  const $ = (id) => document.getElementById(id);
  const TITLE = document.title;
  const rowsBody = $('scene-rows');
  const policyList = $('policies');

  let ros = null;
  let connected = false;
  let reconnectDelay = 500;
  const factors = { velocity: [], steering: [] };
  const rows = new Map(); // uuid hex -> <tr>
  let sceneStates = new Map(); // uuid hex -> the node's /cooperation/scenes entry
  const pendingScenes = new Set(); // uuid hex of scenes with a command in flight
  const pendingPolicies = new Set(); // policy keys with a setting in flight
  let policyRequest = 0; // the newest get_policies; older answers are dropped
  let policyValues = new Map(); // policy key -> the policy get_policies last read

  const { uuidBytes, hex, formatUuid, moduleName, metres, sortKey, setText, setAttr, el } =
    PanelHelpers;

  // --- The message area -----------------------------------------------------------------------

  // The newest message, and a line in the history, newest first.
  function say(kind, text) {
    const area = $('message');
    area.dataset.kind = kind;
    area.textContent = text;
    const history = $('history');
    const time = new Date().toLocaleTimeString([], { hour12: false });
    history.prepend(el('li', { 'data-kind': kind }, [el('time', {}, [time]), ' ', text]));
    while (history.children.length > HISTORY_LENGTH) history.lastElementChild.remove();
  }

  // --- Connection -----------------------------------------------------------------------------

  function showConnection(state, text) {
    const indicator = $('connection');
    indicator.dataset.state = state;
    setText($('connection-text'), text);
  }

  const givenToken = PanelAccess.takeToken();
  // A token put in the address later (after a refusal, say) is read by loading the page again.
  window.addEventListener('hashchange', () => {
    if (PanelAccess.TOKEN.test(location.hash)) location.reload();
  });

  // What the node says the token makes this panel: `operator`, `module`, `anyone` (a node
  // without credentials), or null before it has said.
  let role = null;
  // The operator decisions the node takes (/whoami): all four, or in the stack mode activate
  // and deactivate only.
  let accepted = new Set(CHOICES.map((choice) => choice.decision));
  const operates = () => role === 'operator' || role === 'anyone';

  // Tries again after `delay` ms (or the next step of the backoff), saying why it is not
  // connected.
  function retry(text, delay) {
    const wait = delay || reconnectDelay;
    reconnectDelay = Math.min(reconnectDelay * 2, 5000);
    showConnection('disconnected', `${text}; trying again in ${(wait / 1000).toFixed(1)} s`);
    setTimeout(connect, wait);
  }

  // Asks the node who the token makes this panel first, and connects only if that can work.
  async function connect() {
    showConnection('connecting', `Connecting to ${location.host}…`);
    const next = PanelAccess.judge(await PanelAccess.whoami(givenToken), givenToken, location.host);
    if (next.role) {
      role = next.role;
      document.body.dataset.role = next.role;
    }
    if (next.action === 'retry') {
      retry(next.text, next.delay);
    } else if (next.action === 'refused') {
      showConnection('refused', next.text);
      say('error', next.text);
    } else {
      open(next.answer);
    }
  }

  function open(answer) {
    if (Array.isArray(answer.decisions)) accepted = new Set(answer.decisions);
    const url = `ws://${location.host}/` + (givenToken ? `?token=${givenToken}` : '');
    const client = new ROSLIB.Ros({ url });
    ros = client;
    client.on('connection', () => {
      if (ros !== client) return;
      connected = true;
      reconnectDelay = 500;
      const as = answer.role === 'module'
        ? ` as planning module "${answer.credential}": read-only, no operator controls`
        : answer.credential ? ` as operator "${answer.credential}"` : '';
      showConnection('connected', `Connected to ${location.host}${as}`);
      if (answer.role === 'module') {
        say('warning', `This panel was opened with the token of planning module "${answer.credential}": it shows the scenes and policies, and cannot decide or switch anything. Open it with an operator's token to act.`);
      }
      for (const kind of Object.keys(TOPIC)) {
        const [name, messageType] = TOPIC[kind];
        const topic = new ROSLIB.Topic({ ros: client, name, messageType });
        topic.subscribe((message) => {
          if (ros !== client) return;
          factors[kind] = Array.isArray(message.factors) ? message.factors : [];
          renderScenes();
        });
      }
      const [name, messageType] = SCENES_TOPIC;
      new ROSLIB.Topic({ ros: client, name, messageType }).subscribe((message) => {
        if (ros !== client) return;
        const states = Array.isArray(message.scenes) ? message.scenes : [];
        sceneStates = new Map(states.map((s) => [hex(uuidBytes(s.uuid)), s]));
        renderScenes();
      });
      refreshPolicies();
    });
    client.on('error', () => {});
    client.on('close', () => {
      if (ros !== client) return;
      const wasConnected = connected;
      connected = false;
      ros = null;
      factors.velocity = [];
      factors.steering = [];
      sceneStates = new Map();
      // An answer shown before the connection dropped says nothing of the node now.
      if (wasConnected) say('error', `Connection to ${location.host} lost: the scenes and answers above may be out of date.`);
      pendingScenes.clear();
      pendingPolicies.clear();
      renderScenes();
      renderPolicies(null);
      // The next try asks the node again, which says why if it refuses.
      retry(`Not connected to ${location.host}`);
    });
  }

  // Calls a service; `done(values)` with the response, or `failed(text)` when the node refuses
  // the call itself or does not answer.
  function call(service, args, done, failed) {
    const client = ros;
    if (!client || !connected) {
      failed('not connected to the node');
      return;
    }
    const [name, serviceType] = service;
    let settled = false;
    const timer = setTimeout(() => {
      if (settled) return;
      settled = true;
      failed(`${name}: no answer within ${CALL_TIMEOUT_MS / 1000} s`);
    }, CALL_TIMEOUT_MS);
    const settle = (fn) => (value) => {
      if (settled) return;
      settled = true;
      clearTimeout(timer);
      fn(value);
    };
    new ROSLIB.Service({ ros: client, name, serviceType }).callService(
      new ROSLIB.ServiceRequest(args),
      settle(done),
      settle((error) => failed(`${name}: ${typeof error === 'string' ? error : JSON.stringify(error)}`)),
    );
  }

  // The text of a failed ResponseStatus.
  function refusal(status) {
    const code = status && typeof status.code === 'number' ? ` (code ${status.code})` : '';
    const message = status && status.message ? status.message : 'no explanation given';
    return `${message}${code}`;
  }

  // --- Scenes ---------------------------------------------------------------------------------

  // Whether the vehicle waits on the operator for a scene, by the node's /cooperation/scenes.
  const waits = (uuid) => Boolean(sceneStates.get(uuid)?.awaits_operator);

  // Both streams' scenes (factors with a cooperation status): those waiting for the operator
  // first, then nearest first.
  function scenes() {
    const list = [];
    for (const kind of ['velocity', 'steering']) {
      for (const factor of factors[kind]) {
        const status = Array.isArray(factor.cooperation) ? factor.cooperation[0] : undefined;
        if (!status) continue;
        const bytes = uuidBytes(status.uuid);
        const distances = Array.isArray(factor.distance) ? factor.distance : [factor.distance];
        list.push({
          kind,
          bytes,
          uuid: hex(bytes),
          behavior: factor.behavior || '',
          sequence: factor.sequence || '',
          detail: factor.detail || '',
          direction: kind === 'steering' ? STEERING_DIRECTION[factor.direction] || '' : '',
          distances,
          autonomous: status.autonomous ? status.autonomous.decision : DECISION.UNKNOWN,
          cooperator: status.cooperator ? status.cooperator.decision : DECISION.UNKNOWN,
          cancellable: status.cancellable === true,
        });
      }
    }
    list.sort((a, b) => Number(waits(b.uuid)) - Number(waits(a.uuid))
      || sortKey(a.distances[0]) - sortKey(b.distances[0])
      || sortKey(a.distances[1]) - sortKey(b.distances[1])
      || (a.uuid < b.uuid ? -1 : a.uuid > b.uuid ? 1 : 0));
    return list;
  }

  // A module that reports a scene unsafe decides to deactivate it.
  const unsafe = (scene) => scene.autonomous === DECISION.DEACTIVATE;
  // The operator activated a scene its module reports unsafe.
  const overridden = (scene) => unsafe(scene) && scene.cooperator === DECISION.ACTIVATE;

  // Why the vehicle waits on the operator for a scene.
  function whyWaiting(scene, state) {
    const why = [];
    // The policy that applies is required when the module asks, whatever its module's policy:
    // that one is read from get_policies.
    const configured = policyValues.get(`${scene.behavior}/${scene.sequence}`);
    if (configured === POLICY.REQUIRED || (state.policy === POLICY.REQUIRED && !state.requested)) why.push('policy required');
    if (state.requested) why.push('its module asks');
    if (unsafe(scene)) why.push('its module says unsafe');
    return why.length ? why.join(', ') : 'no decision yet';
  }

  // A row's line of what matters most about its scene, and its kind.
  function flags(scene, state) {
    if (state && state.awaits_operator) return ['waiting', `Waiting for you: ${whyWaiting(scene, state)}`];
    if (overridden(scene)) return ['override', 'Overridden by you: its module says unsafe'];
    if (unsafe(scene)) return ['unsafe', 'Unsafe, its module says'];
    return ['none', ''];
  }

  function newRow(scene) {
    const module = el('span', { class: 'module', 'data-col': 'module' });
    const sub = el('span', { class: 'sub', 'data-col': 'about' });
    const id = el('span', { class: 'sub uuid', 'data-col': 'uuid' });
    const why = el('span', { class: 'flags', 'data-col': 'why' });
    const buttons = CHOICES.map(({ decision, label }) => {
      // A button as wide as its confirming label, so that nothing moves when it appears.
      const labels = [el('span', { class: 'label' }, [label])];
      if (decision === DECISION.ACTIVATE) labels.push(el('span', { class: 'confirm-label' }, [`Confirm ${label.toLowerCase()}`]));
      const button = el('button', { type: 'button', 'data-decision': String(decision), 'aria-pressed': 'false' }, labels);
      button.addEventListener('click', () => command(row, decision));
      return button;
    });
    const group = el('div', { class: 'decide', role: 'group' }, buttons);
    const row = el('tr', { 'data-uuid': scene.uuid, id: `scene-${scene.uuid}` }, [
      el('td', { class: 'module-cell' }, [module, why, sub, id]),
      el('td', { class: 'distance', 'data-col': 'distance', 'data-label': 'Distance' }),
      el('td', { 'data-label': 'Module decision' }, [el('span', { class: 'badge', 'data-col': 'autonomous' })]),
      el('td', { 'data-label': 'Operator decision' }, [el('span', { class: 'badge', 'data-col': 'cooperator' })]),
      el('td', { 'data-label': 'Merged' }, [el('span', { class: 'badge', 'data-col': 'merged' })]),
      el('td', { class: 'age', 'data-col': 'age', 'data-label': 'Since report' }),
      el('td', { 'data-col': 'cancellable', 'data-label': 'Cancellable' }),
      el('td', { class: 'decide-cell' }, [group]),
    ]);
    return row;
  }

  function updateRow(row, scene) {
    const cell = (name) => row.querySelector(`[data-col="${name}"]`);
    const name = moduleName(scene.behavior, scene.sequence);
    row.scene = scene;
    setAttr(row, 'data-ended', 'false');
    setAttr(row, 'data-kind', scene.kind);
    setAttr(row, 'data-cancellable', String(scene.cancellable));
    setText(cell('module'), name);
    const about = [scene.kind === 'steering' ? `steering${scene.direction ? `, ${scene.direction}` : ''}` : 'velocity'];
    if (scene.detail) about.push(scene.detail);
    setText(cell('about'), about.join(' · '));
    setText(cell('uuid'), formatUuid(scene.uuid));
    // What the node's core says of the scene beyond the AD API's status.
    const state = sceneStates.get(scene.uuid);
    const merged = state && state.merged ? state.merged.decision : DECISION.UNKNOWN;
    setAttr(cell('merged'), 'data-decision', String(merged));
    setText(cell('merged'), state ? DECISION_NAME[merged] || String(merged) : '—');
    const [flag, line] = flags(scene, state);
    setAttr(row, 'data-waiting', String(flag === 'waiting'));
    setAttr(row, 'data-unsafe', String(unsafe(scene)));
    setAttr(row, 'data-override', String(overridden(scene)));
    setAttr(cell('why'), 'data-flag', flag);
    setText(cell('why'), line);
    setAttr(cell('why'), 'title', line);
    const age = state && typeof state.age_ms === 'number' ? state.age_ms : null;
    setAttr(row, 'data-stale', String(age !== null && age >= STALE_MS));
    setText(cell('age'), age === null ? '—' : `${(age / 1000).toFixed(1)} s`);
    setAttr(cell('age'), 'title', age === null ? '' : `reported ${(age / 1000).toFixed(1)} s ago`);
    setText(cell('distance'), scene.distances.length > 1
      ? `${metres(scene.distances[0])}\n→ ${metres(scene.distances[1])}`
      : metres(scene.distances[0]));
    for (const col of ['autonomous', 'cooperator']) {
      const badge = cell(col);
      setAttr(badge, 'data-decision', String(scene[col]));
      const text = DECISION_NAME[scene[col]] || String(scene[col]);
      setText(badge, text);
    }
    setText(cell('cancellable'), scene.cancellable ? 'yes' : 'no');
    const pending = pendingScenes.has(scene.uuid);
    const group = row.querySelector('.decide');
    setAttr(group, 'aria-label', `Operator decision for ${name} ${formatUuid(scene.uuid)}`);
    setAttr(group, 'aria-busy', String(pending));
    const confirming = row.confirming && row.confirming.until > Date.now() ? row.confirming.decision : null;
    for (const button of group.querySelectorAll('button')) {
      const decision = Number(button.dataset.decision);
      setAttr(button, 'aria-pressed', String(decision === scene.cooperator));
      const taken = accepted.has(decision);
      button.disabled = pending || !scene.cancellable || !operates() || !taken;
      const why = !scene.cancellable ? 'This scene is not cancellable: the node accepts no command for it now'
        : taken ? '' : 'The planning modules behind this node take activate or deactivate only';
      setAttr(button, 'title', why);
      setAttr(button, 'data-confirm', String(decision === confirming));
    }
  }

  // A row whose scene is no longer reported, kept in place while the pointer is over the
  // scenes: its buttons off, and saying so.
  function endRow(row) {
    setAttr(row, 'data-ended', 'true');
    setAttr(row, 'data-waiting', 'false');
    const why = row.querySelector('[data-col="why"]');
    setAttr(why, 'data-flag', 'ended');
    setText(why, 'Ended: no longer reported');
    for (const button of row.querySelectorAll('button')) button.disabled = true;
  }

  // The pointer is over the scenes: rows keep their places (new scenes are added at the end,
  // ended ones stay, marked) until it leaves.
  let held = false;
  rowsBody.addEventListener('pointerenter', () => { held = true; });
  rowsBody.addEventListener('pointerleave', () => {
    held = false;
    renderScenes();
  });

  function renderScenes() {
    const list = scenes();
    const seen = new Set();
    list.forEach((scene, index) => {
      seen.add(scene.uuid);
      let row = rows.get(scene.uuid);
      if (!row) {
        row = newRow(scene);
        rows.set(scene.uuid, row);
        if (held) rowsBody.append(row);
      }
      updateRow(row, scene);
      // Moves only rows out of place, so that a row stays where it is while it can.
      if (!held && rowsBody.children[index] !== row) rowsBody.insertBefore(row, rowsBody.children[index] || null);
    });
    for (const [uuid, row] of rows) {
      if (seen.has(uuid)) continue;
      if (held) {
        endRow(row);
      } else {
        row.remove();
        rows.delete(uuid);
      }
    }
    const waiting = list.filter((scene) => waits(scene.uuid)).length;
    const count = $('waiting-count');
    setAttr(count, 'data-count', String(waiting));
    setText(count, waiting === 0 ? 'No scene waits for you'
      : waiting === 1 ? '1 scene waits for you' : `${waiting} scenes wait for you`);
    const title = waiting ? `(${waiting} waiting) ${TITLE}` : TITLE;
    if (document.title !== title) document.title = title;
    $('no-scenes').hidden = list.length > 0;
    setText($('no-scenes'), connected ? 'No scene is reported.' : 'Not connected: no scenes to show.');
  }

  // Overriding a module that reports the scene unsafe takes a confirming second click.
  const overridesUnsafe = (scene, decision) => decision === DECISION.ACTIVATE && unsafe(scene);

  function command(row, decision) {
    const scene = row.scene;
    const name = `${moduleName(scene.behavior, scene.sequence)} ${formatUuid(scene.uuid)}`;
    const choice = DECISION_NAME[decision];
    const confirmed = row.confirming && row.confirming.decision === decision && row.confirming.until > Date.now();
    row.confirming = null;
    if (overridesUnsafe(scene, decision) && !confirmed) {
      row.confirming = { decision, until: Date.now() + CONFIRM_MS };
      say('warning', `${name}: its module reports it unsafe. Press "Confirm activate" within ${CONFIRM_MS / 1000} s to activate it anyway.`);
      renderScenes();
      setTimeout(renderScenes, CONFIRM_MS + 50);
      return;
    }
    pendingScenes.add(scene.uuid);
    renderScenes();
    const finish = () => {
      pendingScenes.delete(scene.uuid);
      renderScenes();
    };
    const args = { commands: [{ uuid: { uuid: scene.bytes }, cooperator: { decision } }] };
    call(SERVICE.setCommands, args, (response) => {
      finish();
      if (response.status && response.status.success) {
        say('ok', `${name}: ${choice} accepted.`);
      } else {
        say('error', `${name}: ${choice} refused: ${refusal(response.status)}`);
      }
    }, (error) => {
      finish();
      say('error', `${name}: ${choice} not sent: ${error}`);
    });
  }

  // --- Policies -------------------------------------------------------------------------------

  const policyKey = (policy) => `${policy.behavior}/${policy.sequence || ''}`;

  function refreshPolicies() {
    const request = ++policyRequest;
    call(SERVICE.getPolicies, {}, (response) => {
      if (request !== policyRequest) return;
      if (response.status && response.status.success) {
        renderPolicies(response.policies || []);
      } else {
        say('error', `Policies not read: ${refusal(response.status)}`);
      }
    }, (error) => {
      if (request === policyRequest && connected) say('error', `Policies not read: ${error}`);
    });
  }

  function newPolicyItem(policy) {
    const name = moduleName(policy.behavior, policy.sequence);
    const id = `policy-${policy.behavior}${policy.sequence ? `-${policy.sequence}` : ''}`;
    const input = el('input', {
      type: 'checkbox', role: 'switch', id,
      'data-behavior': policy.behavior, 'data-sequence': policy.sequence || '',
    });
    // A click asks for a confirmation first: the switch moves only when the node says so.
    input.addEventListener('click', (event) => {
      const wanted = input.checked ? POLICY.REQUIRED : POLICY.OPTIONAL;
      event.preventDefault();
      if (operates()) askPolicy(item, wanted);
    });
    const label = el('label', { class: 'switch', for: id }, [
      input,
      el('span', { class: 'track', 'aria-hidden': 'true' }),
      el('span', { class: 'name' }, [name]),
      // The switch's own state says it to assistive technology; this says it to the eye.
      el('span', { class: 'state', 'aria-hidden': 'true' }),
    ]);
    const item = el('li', { 'data-policy': policyKey(policy) }, [label]);
    item.policy = policy;
    return item;
  }

  // Draws the node's policies; `null` when there is no node to ask.
  function renderPolicies(policies) {
    if (policies === null) {
      // The last policies read stay in view, dimmed: the node may have changed them since.
      policyList.dataset.stale = 'true';
      for (const input of policyList.querySelectorAll('input')) input.disabled = true;
      return;
    }
    delete policyList.dataset.stale;
    policyValues = new Map(policies.map((policy) => [policyKey(policy), policy.policy]));
    const items = new Map(Array.from(policyList.children, (item) => [item.dataset.policy, item]));
    policies.forEach((policy, index) => {
      const key = policyKey(policy);
      let item = items.get(key);
      if (!item) item = newPolicyItem(policy);
      items.delete(key);
      item.policy = policy;
      const input = item.querySelector('input');
      const required = policy.policy === POLICY.REQUIRED;
      const pending = pendingPolicies.has(key);
      if (!pending) input.checked = required;
      input.disabled = pending || !operates();
      setAttr(item, 'data-value', required ? 'required' : 'optional');
      setText(item.querySelector('.state'), required ? 'required' : 'optional');
      if (policyList.children[index] !== item) policyList.insertBefore(item, policyList.children[index] || null);
    });
    for (const item of items.values()) item.remove();
  }

  // The confirmation of a policy switch, in a modal dialog: nothing else can be clicked
  // meanwhile, and nothing moves. Cancel is the default.
  const dialog = $('policy-dialog');
  let asked = null;
  function askPolicy(item, value) {
    const name = moduleName(item.policy.behavior, item.policy.sequence);
    const required = value === POLICY.REQUIRED;
    asked = { item, value };
    setText($('policy-dialog-title'), `Make ${name} ${required ? 'required' : 'optional'}?`);
    setText($('policy-dialog-text'), required
      ? `Every scene of ${name}, those live now and those to come, will wait for an operator decision before the vehicle acts on it.`
      : `${name}'s module will decide every scene of it that no operator has decided, those live now and those to come.`);
    setText($('policy-dialog-confirm'), required ? 'Make required' : 'Make optional');
    dialog.returnValue = '';
    dialog.showModal();
    $('policy-dialog-cancel').focus();
  }
  $('policy-dialog-cancel').addEventListener('click', () => dialog.close('cancel'));
  $('policy-dialog-confirm').addEventListener('click', () => dialog.close('confirm'));
  dialog.addEventListener('close', () => {
    const answer = asked;
    asked = null;
    if (answer && dialog.returnValue === 'confirm' && operates() && connected) setPolicy(answer.item, answer.value);
  });

  function setPolicy(item, value) {
    const { behavior, sequence } = item.policy;
    const key = policyKey(item.policy);
    const name = moduleName(behavior, sequence);
    const wanted = value === POLICY.REQUIRED ? 'required' : 'optional';
    pendingPolicies.add(key);
    item.querySelector('input').disabled = true;
    const args = { policies: [{ behavior, sequence: sequence || '', policy: value }] };
    call(SERVICE.setPolicies, args, (response) => {
      pendingPolicies.delete(key);
      if (response.status && response.status.success) {
        say('ok', `${name}: policy ${wanted} accepted.`);
      } else {
        say('error', `${name}: policy ${wanted} refused: ${refusal(response.status)}`);
      }
      refreshPolicies();
    }, (error) => {
      pendingPolicies.delete(key);
      say('error', `${name}: policy ${wanted} not sent: ${error}`);
      refreshPolicies();
    });
  }

  setInterval(() => {
    if (connected) refreshPolicies();
  }, POLICY_REFRESH_MS);
  renderScenes();
  connect();
})();
