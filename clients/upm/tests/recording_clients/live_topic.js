// A Foxglove WebSocket client nobody in this project wrote: Foxglove's own
// `@foxglove/ws-protocol` FoxgloveClient over the `ws` package. It
// connects (retrying while the run starts up), subscribes to TOPIC as soon
// as the server advertises it, and requires a message within WINDOW_MS of
// subscribing.
//
// usage: node live_topic.js URL TOPIC CONNECT_TIMEOUT_S WINDOW_MS
// (NODE_PATH must reach the installed packages.)
//
// Prints `first message after X ms` (and what it held) and exits 0, or says
// why not and exits 1.
"use strict";

const { FoxgloveClient } = require("@foxglove/ws-protocol");
const WebSocket = require("ws");

const [url, topic, connectTimeoutS, windowMs] = process.argv.slice(2);
const giveUpAt = Date.now() + Number(connectTimeoutS) * 1000;
const window = Number(windowMs);
let attempts = 0;
// Whatever happens, never wait longer than this for the topic.
setTimeout(() => fail(`${topic} not advertised within ${connectTimeoutS} s`), Number(connectTimeoutS) * 1000 + window);

function fail(why) {
  console.log(`FAIL ${why}`);
  process.exit(1);
}

function attempt() {
  attempts += 1;
  // FoxgloveClient's default subprotocol (foxglove.websocket.v1) is refused
  // by the foxglove SDK 0.30 server; it speaks foxglove.sdk.v1.
  const ws = new WebSocket(url, ["foxglove.sdk.v1"]);
  const client = new FoxgloveClient({ ws });
  let subscribedAt = null;
  let subscription = null;
  let settled = false;

  const retry = (why) => {
    if (settled) return;
    settled = true;
    try {
      client.close();
    } catch (_) {}
    if (Date.now() >= giveUpAt) fail(`no connection to ${url} after ${attempts} attempts: ${why}`);
    setTimeout(attempt, 250);
  };

  client.on("error", (e) => retry(String(e && e.message ? e.message : e)));
  client.on("close", () => {
    if (subscribedAt === null) retry("closed before subscribing");
    else if (!settled) fail(`connection closed ${(performance.now() - subscribedAt).toFixed(1)} ms after subscribing, no message`);
  });
  client.on("serverInfo", (info) => {
    console.log(`connected (attempt ${attempts}): server ${JSON.stringify(info.name)}, capabilities ${JSON.stringify(info.capabilities)}`);
  });
  client.on("advertise", (channels) => {
    if (subscription !== null) return;
    const channel = channels.find((c) => c.topic === topic);
    if (!channel) return;
    console.log(`advertised ${topic}: channel ${channel.id}, encoding ${channel.encoding}, schema ${channel.schemaName} (${channel.schemaEncoding})`);
    subscription = client.subscribe(channel.id);
    subscribedAt = performance.now();
    setTimeout(() => {
      if (!settled) fail(`no message on ${topic} within ${window} ms of subscribing`);
    }, window);
  });
  client.on("message", (event) => {
    if (settled || event.subscriptionId !== subscription) return;
    settled = true;
    const ms = performance.now() - subscribedAt;
    const text = new TextDecoder().decode(event.data);
    let decoded;
    try {
      decoded = JSON.parse(text);
    } catch (e) {
      fail(`message on ${topic} is not JSON: ${e}`);
    }
    const parts = decoded.parts;
    if (!Array.isArray(parts) || parts.length === 0 || typeof parts[0].x !== "number" || typeof parts[0].y !== "number") {
      fail(`message on ${topic} has no parts with x/y: ${text.slice(0, 300)}`);
    }
    console.log(`message: seq ${decoded.seq}, ${parts.length} parts, log time ${event.timestamp} ns`);
    console.log(`first message after ${ms.toFixed(1)} ms`);
    client.close();
    process.exit(ms <= window ? 0 : 1);
  });
}

attempt();
